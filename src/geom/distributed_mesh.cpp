#include "geom/distributed_mesh.hpp"

#include "core/error.hpp"
#include "par/graph_partition.hpp"
#include "par/morton_partition.hpp"

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

std::vector<int> scotch_parts(const par::Comm& comm, const TriangleMesh& mesh) {
  const MeshTopology topology(mesh);
  const auto& neighbors = topology.vertex_neighbors();
  return par::scotch_graph_partition(comm, neighbors.offsets, neighbors.indices, comm.size);
}

} // namespace

DistributedMesh::DistributedMesh(const par::Comm& comm, const TriangleMesh& mesh,
                                 PartitionMethod method)
    : rank_(comm.rank), topology_(TriangleMesh{}) {
  const std::int32_t n = mesh.num_vertices();
  std::vector<int> parts(n, 0);
  if (comm.size > 1)
    parts = method == PartitionMethod::kMorton ? morton_parts(mesh, comm.size)
                                               : scotch_parts(comm, mesh);

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
