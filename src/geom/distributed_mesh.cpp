#include "geom/distributed_mesh.hpp"

#include "core/error.hpp"
#include "par/morton_partition.hpp"
#include "par/petsc_handle.hpp"
#include "par/petsc_session.hpp"

#include <petscmat.h>
#include <scotch/scotch.h>

#include <algorithm>
#include <numeric>
#include <tuple>

namespace texsim::geom {
namespace {

std::vector<std::array<double, 3>> points_of(const TriangleMesh& mesh) {
  std::vector<std::array<double, 3>> points(mesh.positions.size());
  for (std::size_t v = 0; v < points.size(); ++v)
    points[v] = {mesh.positions[v].x(), mesh.positions[v].y(), mesh.positions[v].z()};
  return points;
}

std::vector<int> morton_parts(const TriangleMesh& mesh, int parts) {
  return par::morton_partition(points_of(mesh), parts);
}

// PT-Scotch through PETSc: each rank describes a block of rows of the vertex graph, PETSc returns
// the part of each of its rows, and the parts are gathered so every rank knows all of them.
std::vector<int> ptscotch_parts(const par::Comm& comm, const TriangleMesh& mesh) {
  const MeshTopology topology(mesh);
  const auto& neighbors = topology.vertex_neighbors();
  const PetscInt n = mesh.num_vertices();
  const PetscInt first = PetscInt(std::int64_t(n) * comm.rank / comm.size);
  const PetscInt last = PetscInt(std::int64_t(n) * (comm.rank + 1) / comm.size);
  // MatCreateMPIAdj takes ownership of ia/ja, which must come from PetscMalloc.
  PetscInt* ia = nullptr;
  PetscInt* ja = nullptr;
  const PetscInt entries = PetscInt(neighbors.offsets[last] - neighbors.offsets[first]);
  TEXSIM_PETSC_CALL(PetscMalloc1(last - first + 1, &ia));
  TEXSIM_PETSC_CALL(PetscMalloc1(std::max<PetscInt>(entries, 1), &ja));
  ia[0] = 0;
  for (PetscInt v = first; v < last; ++v) {
    const auto row = neighbors.row(v);
    std::copy(row.begin(), row.end(), ja + ia[v - first]);
    ia[v - first + 1] = ia[v - first] + PetscInt(row.size());
  }
  par::PetscMat adjacency;
  TEXSIM_PETSC_CALL(
      MatCreateMPIAdj(comm.raw, last - first, n, ia, ja, nullptr, adjacency.address()));
  // Scotch seeds its random generator from the clock unless told otherwise: a fixed seed makes
  // the partition, and so the run, the same every time.
  SCOTCH_randomSeed(1);
  SCOTCH_randomReset();
  par::PetscMatPartitioning partitioning;
  TEXSIM_PETSC_CALL(MatPartitioningCreate(comm.raw, partitioning.address()));
  TEXSIM_PETSC_CALL(MatPartitioningSetAdjacency(partitioning, adjacency));
  TEXSIM_PETSC_CALL(MatPartitioningSetType(partitioning, MATPARTITIONINGPTSCOTCH));
  TEXSIM_PETSC_CALL(MatPartitioningSetNParts(partitioning, comm.size));
  par::PetscIs local_parts;
  TEXSIM_PETSC_CALL(MatPartitioningApply(partitioning, local_parts.address()));

  const PetscInt* values = nullptr;
  TEXSIM_PETSC_CALL(ISGetIndices(local_parts, &values));
  std::vector<int> mine(values, values + (last - first));
  TEXSIM_PETSC_CALL(ISRestoreIndices(local_parts, &values));
  std::vector<int> counts(comm.size), displacements(comm.size);
  for (int r = 0; r < comm.size; ++r) {
    displacements[r] = int(std::int64_t(n) * r / comm.size);
    counts[r] = int(std::int64_t(n) * (r + 1) / comm.size) - displacements[r];
  }
  std::vector<int> parts(n);
  MPI_Allgatherv(mine.data(), int(mine.size()), MPI_INT, parts.data(), counts.data(),
                 displacements.data(), MPI_INT, comm.raw);
  return parts;
}

} // namespace

DistributedMesh::DistributedMesh(const par::Comm& comm, const TriangleMesh& mesh,
                                 PartitionMethod method)
    : rank_(comm.rank), topology_(TriangleMesh{}) {
  const std::int32_t n = mesh.num_vertices();
  std::vector<int> parts(n, 0);
  if (comm.size > 1)
    parts = method == PartitionMethod::kMorton ? morton_parts(mesh, comm.size)
                                               : ptscotch_parts(comm, mesh);

  // Global order: by owning rank, so each rank's range is contiguous, then along a Morton curve
  // so neighbours sit close in memory (measured on a level-7 icosphere: ICC-preconditioned CG
  // needs 23 iterations instead of 33 in input order); ties by input id.
  const auto keys = par::morton_keys(points_of(mesh));
  std::vector<std::int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return std::tie(parts[a], keys[a], a) < std::tie(parts[b], keys[b], b);
  });
  std::vector<std::int32_t> new_id(n);
  input_id_.resize(n);
  mesh_.positions.resize(n);
  for (std::int32_t g = 0; g < n; ++g) {
    new_id[order[g]] = g;
    input_id_[g] = order[g];
    mesh_.positions[g] = mesh.positions[order[g]];
  }
  mesh_.triangles = mesh.triangles;
  for (auto& triangle : mesh_.triangles)
    for (auto& v : triangle)
      v = new_id[v];
  owner_begin_.assign(comm.size + 1, 0);
  for (int part : parts)
    ++owner_begin_[part + 1];
  std::partial_sum(owner_begin_.begin(), owner_begin_.end(), owner_begin_.begin());
  topology_ = MeshTopology(mesh_);

  const std::int32_t begin = owned_begin(), end = owned_end();
  const auto& neighbors = topology_.vertex_neighbors();
  const auto& vertex_triangles = topology_.vertex_triangles();
  for (std::int32_t v = begin; v < end; ++v) {
    for (const std::int32_t w : neighbors.row(v))
      if (w < begin || w >= end)
        ghosts_.push_back(w);
    for (const std::int32_t t : vertex_triangles.row(v))
      assembly_triangles_.push_back(t);
  }
  for (auto* list : {&ghosts_, &assembly_triangles_}) {
    std::sort(list->begin(), list->end());
    list->erase(std::unique(list->begin(), list->end()), list->end());
  }
  for (const std::int32_t t : assembly_triangles_) {
    const auto& tri = mesh_.triangles[t];
    const std::int32_t smallest = std::min({tri[0], tri[1], tri[2]});
    if (smallest >= begin && smallest < end)
      owned_triangles_.push_back(t);
  }

  for (const auto& edge : topology_.edges())
    quality_.edge_cut += owner(edge[0]) != owner(edge[1]);
  std::int32_t most = 0;
  for (int r = 0; r < comm.size; ++r)
    most = std::max(most, owner_begin_[r + 1] - owner_begin_[r]);
  quality_.imbalance = n > 0 ? double(most) * comm.size / n : 1.0;
  std::int64_t ghosts = std::int64_t(ghosts_.size());
  MPI_Allreduce(&ghosts, &quality_.ghosts_max, 1, MPI_INT64_T, MPI_MAX, comm.raw);
}

int DistributedMesh::owner(std::int32_t vertex) const {
  const auto it = std::upper_bound(owner_begin_.begin(), owner_begin_.end(), vertex);
  return int(it - owner_begin_.begin()) - 1;
}

std::int32_t DistributedMesh::local_index(std::int32_t vertex) const {
  if (vertex >= owned_begin() && vertex < owned_end())
    return vertex - owned_begin();
  const auto it = std::lower_bound(ghosts_.begin(), ghosts_.end(), vertex);
  if (it == ghosts_.end() || *it != vertex)
    return -1;
  return owned_count() + std::int32_t(it - ghosts_.begin());
}

std::int32_t DistributedMesh::global_index(std::int32_t local) const {
  return local < owned_count() ? owned_begin() + local : ghosts_[local - owned_count()];
}

void DistributedMesh::set_positions(const std::vector<Vec3>& positions) {
  TEXSIM_VERIFY(positions.size() == mesh_.positions.size(),
                "set_positions: " << positions.size() << " positions for " << mesh_.positions.size()
                                  << " vertices");
  mesh_.positions = positions;
}

std::vector<double> DistributedMesh::gather(const par::Comm& comm, std::span<const double> owned,
                                            int components) const {
  TEXSIM_VERIFY(owned.size() == std::size_t(owned_count()) * components,
                "gather: " << owned.size() << " values for " << owned_count() << " vertices x "
                           << components);
  std::vector<int> counts(comm.size), displacements(comm.size);
  for (int r = 0; r < comm.size; ++r) {
    displacements[r] = owner_begin_[r] * components;
    counts[r] = (owner_begin_[r + 1] - owner_begin_[r]) * components;
  }
  std::vector<double> all(std::size_t(global_count()) * components);
  MPI_Allgatherv(owned.data(), int(owned.size()), MPI_DOUBLE, all.data(), counts.data(),
                 displacements.data(), MPI_DOUBLE, comm.raw);
  return all;
}

} // namespace texsim::geom
