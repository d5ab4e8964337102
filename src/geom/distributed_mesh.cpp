#include "geom/distributed_mesh.hpp"

#include "core/error.hpp"
#include "core/stage_timers.hpp"
#include "par/collective.hpp"
#include "par/graph_partition.hpp"
#include "par/morton_partition.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstring>
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

/// One rank's part as rank 0 cuts it from the whole mesh: its local vertices (global ids, input
/// ids, positions) and its triangles in local numbering.
struct Part {
  std::int32_t ghost_count = 0;
  std::vector<std::int32_t> global_id;
  std::vector<std::int64_t> input_id;
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
};

/// The whole mesh on rank 0, renumbered by owner, and what it takes to cut each rank's part.
class RootPartition {
public:
  RootPartition(const TriangleMesh& input, PartitionMethod method, int ranks)
      : vertex_stamp_(std::size_t(input.num_vertices()), -1),
        triangle_stamp_(std::size_t(input.num_triangles()), -1),
        local_of_(std::size_t(input.num_vertices()), -1) {
    const std::int32_t n = input.num_vertices();
    std::vector<int> parts(n, 0);
    if (ranks > 1 && method == PartitionMethod::kMorton)
      parts = par::morton_partition(points_of(input), ranks);
    if (ranks > 1 && method == PartitionMethod::kScotch) {
      const MeshTopology topology(input);
      const auto& neighbors = topology.vertex_neighbors();
      parts = par::scotch_graph_partition_serial(neighbors.offsets, neighbors.indices, ranks);
    }
    // Global order: by owning rank, so each rank's range is contiguous, then along a Morton
    // curve so neighbours sit close in memory (measured on a level-7 icosphere: ICC-
    // preconditioned CG needs 23 iterations instead of 33 in input order); ties by input id.
    const auto keys = par::morton_keys(points_of(input));
    std::vector<std::int32_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
      return std::tie(parts[a], keys[a], a) < std::tie(parts[b], keys[b], b);
    });
    std::vector<std::int32_t> new_id(n);
    mesh_.positions.resize(n);
    input_id_.resize(n);
    for (std::int32_t g = 0; g < n; ++g) {
      new_id[order[g]] = g;
      input_id_[g] = order[g];
      mesh_.positions[g] = input.positions[order[g]];
    }
    mesh_.triangles = input.triangles;
    for (auto& triangle : mesh_.triangles)
      for (auto& v : triangle)
        v = new_id[v];
    owner_begin_.assign(ranks + 1, 0);
    for (int part : parts)
      ++owner_begin_[part + 1];
    std::partial_sum(owner_begin_.begin(), owner_begin_.end(), owner_begin_.begin());
    topology_ = std::make_unique<MeshTopology>(mesh_);
    for (const auto& edge : topology_->edges())
      edge_cut_ += owner(edge[0]) != owner(edge[1]);
  }

  const std::vector<std::int32_t>& owner_begin() const { return owner_begin_; }
  std::int64_t edge_cut() const { return edge_cut_; }
  std::int64_t triangle_count() const { return std::int64_t(mesh_.triangles.size()); }

  /// Rank r's owned vertices, ghosts and outer halo, and the triangles within kHaloRings rings.
  Part part(int r) {
    const std::int32_t begin = owner_begin_[r], end = owner_begin_[r + 1];
    std::vector<std::int32_t> ring(std::size_t(end - begin));
    std::iota(ring.begin(), ring.end(), begin);
    for (const std::int32_t v : ring)
      vertex_stamp_[v] = r;
    // Ring by ring: the triangles touching the previous ring's vertices, and their new vertices.
    std::vector<std::int32_t> triangles, ghosts, outer;
    for (int level = 0; level < DistributedMesh::kHaloRings; ++level) {
      std::vector<std::int32_t> next;
      for (const std::int32_t v : ring)
        for (const std::int32_t t : topology_->vertex_triangles().row(v)) {
          if (triangle_stamp_[t] == r)
            continue;
          triangle_stamp_[t] = r;
          triangles.push_back(t);
          for (const std::int32_t w : mesh_.triangles[t])
            if (vertex_stamp_[w] != r) {
              vertex_stamp_[w] = r;
              next.push_back(w);
            }
        }
      auto& into = level == 0 ? ghosts : outer;
      into.insert(into.end(), next.begin(), next.end());
      ring = std::move(next);
    }
    std::sort(ghosts.begin(), ghosts.end());
    std::sort(outer.begin(), outer.end());
    std::sort(triangles.begin(), triangles.end());

    Part part;
    part.ghost_count = std::int32_t(ghosts.size());
    part.global_id.resize(std::size_t(end - begin));
    std::iota(part.global_id.begin(), part.global_id.end(), begin);
    part.global_id.insert(part.global_id.end(), ghosts.begin(), ghosts.end());
    part.global_id.insert(part.global_id.end(), outer.begin(), outer.end());
    for (std::size_t local = 0; local < part.global_id.size(); ++local) {
      const std::int32_t g = part.global_id[local];
      local_of_[g] = std::int32_t(local);
      part.input_id.push_back(input_id_[g]);
      part.positions.push_back(mesh_.positions[g]);
    }
    for (const std::int32_t t : triangles) {
      const auto& tri = mesh_.triangles[t];
      part.triangles.push_back({local_of_[tri[0]], local_of_[tri[1]], local_of_[tri[2]]});
    }
    return part;
  }

private:
  int owner(std::int32_t v) const {
    return int(std::upper_bound(owner_begin_.begin(), owner_begin_.end(), v) -
               owner_begin_.begin()) -
           1;
  }

  TriangleMesh mesh_;
  std::unique_ptr<MeshTopology> topology_;
  std::vector<std::int64_t> input_id_;
  std::vector<std::int32_t> owner_begin_;
  std::int64_t edge_cut_ = 0;
  // Scratch of part(): the last rank whose part met each vertex and triangle, local numbers.
  std::vector<int> vertex_stamp_;
  std::vector<int> triangle_stamp_;
  std::vector<std::int32_t> local_of_;
};

/// A part as one message: counts, then each array's bytes.
std::vector<std::byte> pack(const Part& part) {
  const std::int64_t header[3] = {part.ghost_count, std::int64_t(part.global_id.size()),
                                  std::int64_t(part.triangles.size())};
  std::vector<std::byte> bytes;
  const auto append = [&](const void* data, std::size_t size) {
    const auto* first = static_cast<const std::byte*>(data);
    bytes.insert(bytes.end(), first, first + size);
  };
  append(header, sizeof header);
  append(part.global_id.data(), part.global_id.size() * sizeof(std::int32_t));
  append(part.input_id.data(), part.input_id.size() * sizeof(std::int64_t));
  append(part.positions.data(), part.positions.size() * sizeof(Vec3));
  append(part.triangles.data(), part.triangles.size() * sizeof(Triangle));
  return bytes;
}

Part unpack(const std::vector<std::byte>& bytes) {
  std::size_t offset = 0;
  const auto take = [&](void* data, std::size_t size) {
    TEXSIM_VERIFY(offset + size <= bytes.size(), "DistributedMesh: truncated part message");
    std::memcpy(data, bytes.data() + offset, size);
    offset += size;
  };
  std::int64_t header[3];
  take(header, sizeof header);
  Part part;
  part.ghost_count = std::int32_t(header[0]);
  part.global_id.resize(std::size_t(header[1]));
  part.input_id.resize(std::size_t(header[1]));
  part.positions.resize(std::size_t(header[1]));
  part.triangles.resize(std::size_t(header[2]));
  take(part.global_id.data(), part.global_id.size() * sizeof(std::int32_t));
  take(part.input_id.data(), part.input_id.size() * sizeof(std::int64_t));
  take(part.positions.data(), part.positions.size() * sizeof(Vec3));
  take(part.triangles.data(), part.triangles.size() * sizeof(Triangle));
  return part;
}

constexpr int kPartTag = 4711;

} // namespace

DistributedMesh::DistributedMesh(const par::Comm& comm, const TriangleMesh& root_mesh,
                                 PartitionMethod method)
    : comm_(comm), rank_(comm.rank), topology_(TriangleMesh{}) {
  const double start_s = wall_seconds();
  std::unique_ptr<RootPartition> root;
  par::run_collectively(comm, [&] {
    if (comm.is_root())
      root = std::make_unique<RootPartition>(root_mesh, method, comm.size);
  });
  owner_begin_.resize(std::size_t(comm.size) + 1);
  std::int64_t counts[2] = {0, 0};
  if (root) {
    owner_begin_ = root->owner_begin();
    counts[0] = root->edge_cut();
    counts[1] = root->triangle_count();
  }
  MPI_Bcast(owner_begin_.data(), comm.size + 1, MPI_INT32_T, 0, comm.raw);
  MPI_Bcast(counts, 2, MPI_INT64_T, 0, comm.raw);
  quality_.edge_cut = counts[0];
  global_triangles_ = counts[1];

  // Rank 0 cuts the parts one at a time and sends each as it is cut, so it never holds more
  // than the whole mesh and one part.
  Part part;
  if (root) {
    for (int r = 1; r < comm.size; ++r) {
      const auto bytes = pack(root->part(r));
      TEXSIM_VERIFY(bytes.size() < std::size_t(INT32_MAX),
                    "DistributedMesh: rank " << r << "'s part exceeds 2 GiB; use more ranks");
      MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, r, kPartTag, comm.raw);
    }
    part = root->part(0);
    root.reset();
    root_seconds_ = wall_seconds() - start_s;
  } else {
    MPI_Status status;
    MPI_Probe(0, kPartTag, comm.raw, &status);
    int size = 0;
    MPI_Get_count(&status, MPI_BYTE, &size);
    std::vector<std::byte> bytes(static_cast<std::size_t>(size));
    MPI_Recv(bytes.data(), size, MPI_BYTE, 0, kPartTag, comm.raw, MPI_STATUS_IGNORE);
    part = unpack(bytes);
  }

  ghost_count_ = part.ghost_count;
  global_id_ = std::move(part.global_id);
  input_id_ = std::move(part.input_id);
  mesh_.positions = std::move(part.positions);
  mesh_.triangles = std::move(part.triangles);
  topology_ = MeshTopology(mesh_);

  const std::int32_t owned = owned_count();
  for (std::int32_t t = 0; t < mesh_.num_triangles(); ++t) {
    const auto& tri = mesh_.triangles[t];
    if (std::min({tri[0], tri[1], tri[2]}) >= owned)
      continue;
    assembly_triangles_.push_back(t);
    const std::int32_t smallest =
        std::min({global_id_[tri[0]], global_id_[tri[1]], global_id_[tri[2]]});
    if (smallest >= owned_begin() && smallest < owned_end())
      owned_triangles_.push_back(t);
  }

  std::int32_t most = 0;
  for (int r = 0; r < comm.size; ++r)
    most = std::max(most, owner_begin_[r + 1] - owner_begin_[r]);
  quality_.imbalance = global_count() > 0 ? double(most) * comm.size / global_count() : 1.0;
  const std::int64_t mine[2] = {ghost_count_, std::int64_t(global_id_.size()) - owned};
  std::int64_t most_halo[2];
  MPI_Allreduce(mine, most_halo, 2, MPI_INT64_T, MPI_MAX, comm.raw);
  quality_.ghosts_max = most_halo[0];
  quality_.halo_max = most_halo[1];
  MPI_Bcast(&root_seconds_, 1, MPI_DOUBLE, 0, comm.raw);
}

std::span<const std::int32_t> DistributedMesh::ghosts() const {
  return std::span(global_id_).subspan(std::size_t(owned_count()), std::size_t(ghost_count_));
}

std::int32_t DistributedMesh::local_index(std::int32_t vertex) const {
  if (vertex >= owned_begin() && vertex < owned_end())
    return vertex - owned_begin();
  // Ghosts and the outer halo are each sorted by global id.
  const auto find_in = [&](std::size_t first, std::size_t last) -> std::int32_t {
    const auto begin = global_id_.begin() + std::ptrdiff_t(first);
    const auto end = global_id_.begin() + std::ptrdiff_t(last);
    const auto it = std::lower_bound(begin, end, vertex);
    return it != end && *it == vertex ? std::int32_t(it - global_id_.begin()) : -1;
  };
  const std::int32_t ghost = find_in(std::size_t(owned_count()), std::size_t(local_count()));
  return ghost >= 0 ? ghost : find_in(std::size_t(local_count()), global_id_.size());
}

void DistributedMesh::set_positions(const std::vector<Vec3>& positions) {
  TEXSIM_VERIFY(positions.size() == mesh_.positions.size(),
                "set_positions: " << positions.size() << " positions for " << mesh_.positions.size()
                                  << " local vertices");
  mesh_.positions = positions;
}

void DistributedMesh::set_owned_positions(std::span<const double> owned_xyz) {
  TEXSIM_VERIFY(owned_xyz.size() == 3 * std::size_t(owned_count()),
                "set_owned_positions: " << owned_xyz.size() << " coordinates for " << owned_count()
                                        << " owned vertices");
  std::vector<double> xyz(3 * mesh_.positions.size());
  std::copy(owned_xyz.begin(), owned_xyz.end(), xyz.begin());
  update_halo(xyz, 3);
  for (std::size_t v = 0; v < mesh_.positions.size(); ++v)
    mesh_.positions[v] = Vec3(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
}

par::GhostedVector& DistributedMesh::halo_vector(int components) const {
  auto& vector = halo_vectors_[components];
  if (!vector) {
    const auto halo = std::span(global_id_).subspan(std::size_t(owned_count()));
    vector = std::make_unique<par::GhostedVector>(comm_, owned_count(), halo, components);
  }
  return *vector;
}

void DistributedMesh::update_halo(std::span<double> values, int components) const {
  TEXSIM_VERIFY(values.size() == std::size_t(components) * global_id_.size(),
                "update_halo: " << values.size() << " values for " << global_id_.size()
                                << " local vertices x " << components);
  auto& vector = halo_vector(components);
  const std::size_t owned = std::size_t(components) * std::size_t(owned_count());
  vector.set_owned(values.first(owned));
  const auto local = vector.local();
  std::copy(local.begin() + std::ptrdiff_t(owned), local.end(),
            values.begin() + std::ptrdiff_t(owned));
}

} // namespace texsim::geom
