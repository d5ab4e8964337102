#include "geom/distributed_mesh.hpp"

#include "core/error.hpp"
#include "core/stage_timers.hpp"
#include "geom/morton_order.hpp"
#include "par/collective.hpp"
#include "par/graph_partition.hpp"
#include "par/morton_partition.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>
#include <tuple>

namespace texsim::geom {
namespace {

/// One rank's coarse triangles and the rings around them, as rank 0 cuts them, with what the rank
/// needs to refine them and to tell which fine vertices are its own.
struct CoarsePart {
  CoarsePatch patch;
  std::vector<std::int32_t> triangle_owner; ///< rank owning each patch triangle
  std::vector<std::int32_t> triangle_ring;  ///< 0: the rank's own, k: k rings out
};

/// Coarse rings a part needs around its own triangles after `rounds` rounds of refinement: enough
/// for kHaloRings fine rings of halo, plus one for the refinement masks and for the fans of the
/// halo's vertices. Crossing a ring of coarse triangles takes at least n / 2 fine edges (n = 2^R;
/// a point on a ring's border is within n / 2 of one of its edge's ends, whose fan reaches n out),
/// and exactly one at n = 1.
int coarse_halo_rings(int rounds) {
  const int n = 1 << rounds;
  const int fine_rings = DistributedMesh::kHaloRings;
  return (n == 1 ? fine_rings : (2 * fine_rings + n - 1) / n) + 1;
}

/// The coarse mesh on rank 0, its triangles partitioned, and what it takes to cut each part.
class CoarsePartition {
public:
  CoarsePartition(const TriangleMesh& coarse, std::span<const char> creases, PartitionMethod method,
                  int ranks, int rings)
      : topology_(coarse), cutter_(coarse, topology_, creases), rings_(rings) {
    const std::int32_t triangles = coarse.num_triangles();
    std::vector<int> owner(std::size_t(triangles), 0);
    if (ranks > 1 && method == PartitionMethod::kMorton)
      owner = morton_triangle_parts(coarse, ranks);
    if (ranks > 1 && method == PartitionMethod::kScotch) {
      // The dual graph: triangles joined across their edges.
      std::vector<std::int64_t> offsets{0};
      std::vector<std::int32_t> neighbours;
      for (std::int32_t t = 0; t < triangles; ++t) {
        for (const std::int32_t e : topology_.triangle_edges(t))
          for (const std::int32_t u : topology_.edge_triangles(e))
            if (u != t)
              neighbours.push_back(u);
        offsets.push_back(std::int64_t(neighbours.size()));
      }
      owner = par::scotch_graph_partition_serial(offsets, neighbours, ranks);
    }
    owner_.assign(owner.begin(), owner.end());
    by_rank_.assign(std::size_t(ranks), {});
    for (std::int32_t t = 0; t < triangles; ++t)
      by_rank_[owner_[t]].push_back(t);
  }

  std::int64_t triangle_count() const { return topology_.num_triangles(); }

  /// Rank r's triangles and `rings` rings of triangles sharing a vertex with them.
  CoarsePart part(int r) {
    CoarsePart part;
    part.patch = cutter_.cut(by_rank_[r], rings_, &part.triangle_ring);
    for (const std::int64_t t : part.patch.triangle_id)
      part.triangle_owner.push_back(owner_[t]);
    return part;
  }

private:
  MeshTopology topology_;
  PatchCutter cutter_;
  int rings_;
  std::vector<std::int32_t> owner_;
  std::vector<std::vector<std::int32_t>> by_rank_;
};

/// Writes arrays of plain values into one message, each after its length.
class ByteWriter {
public:
  template <typename T> void operator()(const std::vector<T>& values) {
    const std::int64_t size = std::int64_t(values.size());
    append(&size, sizeof size);
    append(values.data(), values.size() * sizeof(T));
  }
  std::vector<std::byte>& bytes() { return bytes_; }

private:
  void append(const void* data, std::size_t size) {
    const auto* first = static_cast<const std::byte*>(data);
    bytes_.insert(bytes_.end(), first, first + size);
  }
  std::vector<std::byte> bytes_;
};

/// Reads back what ByteWriter wrote, in the same order.
class ByteReader {
public:
  explicit ByteReader(std::vector<std::byte> bytes) : bytes_(std::move(bytes)) {}
  template <typename T> void operator()(std::vector<T>& values) {
    std::int64_t size = 0;
    read(&size, sizeof size);
    values.resize(std::size_t(size));
    read(values.data(), values.size() * sizeof(T));
  }

private:
  void read(void* data, std::size_t size) {
    TEXSIM_VERIFY(offset_ + size <= bytes_.size(), "DistributedMesh: truncated part message");
    std::memcpy(data, bytes_.data() + offset_, size);
    offset_ += size;
  }
  std::vector<std::byte> bytes_;
  std::size_t offset_ = 0;
};

/// Every array of a part, in message order, passed to `visit` (ByteWriter or ByteReader).
template <typename Part, typename Visitor> void visit_arrays(Part& part, Visitor& visit) {
  visit(part.patch.mesh.positions);
  visit(part.patch.mesh.triangles);
  visit(part.patch.vertex_id);
  visit(part.patch.triangle_id);
  visit(part.patch.triangle_edge_id);
  visit(part.patch.triangle_edge_crease);
  visit(part.triangle_owner);
  visit(part.triangle_ring);
}

std::vector<std::byte> pack(const CoarsePart& part) {
  ByteWriter writer;
  writer(std::vector<std::int64_t>{part.patch.coarse_vertices, part.patch.coarse_edges});
  visit_arrays(part, writer);
  return std::move(writer.bytes());
}

CoarsePart unpack(std::vector<std::byte> bytes) {
  ByteReader reader(std::move(bytes));
  CoarsePart part;
  std::vector<std::int64_t> counts;
  reader(counts);
  TEXSIM_VERIFY(counts.size() == 2, "DistributedMesh: malformed part message");
  part.patch.coarse_vertices = counts[0];
  part.patch.coarse_edges = counts[1];
  visit_arrays(part, reader);
  return part;
}

/// Rank 0 cuts the parts one at a time and sends each as it is cut, so it never holds more than
/// the coarse mesh and one part. Returns this rank's part. Collective.
CoarsePart scatter_parts(const par::Comm& comm, std::unique_ptr<CoarsePartition> root) {
  constexpr int kPartTag = 4711;
  if (root) {
    for (int r = 1; r < comm.size; ++r) {
      const auto bytes = pack(root->part(r));
      TEXSIM_VERIFY(bytes.size() < std::size_t(INT32_MAX),
                    "DistributedMesh: rank " << r << "'s part exceeds 2 GiB; use more ranks");
      MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, r, kPartTag, comm.raw);
    }
    return root->part(0);
  }
  MPI_Status status;
  MPI_Probe(0, kPartTag, comm.raw, &status);
  int size = 0;
  MPI_Get_count(&status, MPI_BYTE, &size);
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  MPI_Recv(bytes.data(), size, MPI_BYTE, 0, kPartTag, comm.raw, MPI_STATUS_IGNORE);
  return unpack(std::move(bytes));
}

/// The owner of every fine vertex: the owner of the coarse triangle of smallest id among those
/// its cell (coarse vertex, edge or triangle) lies on. Exact wherever the part holds the cell's
/// whole fan, which includes every vertex within the fine halo.
std::vector<std::int32_t> fine_owners(const CoarsePart& part, const RefinedPatch& fine) {
  std::vector<std::int64_t> smallest(fine.mesh.positions.size(),
                                     std::numeric_limits<std::int64_t>::max());
  std::vector<std::int32_t> owner(fine.mesh.positions.size(), -1);
  for (std::size_t t = 0; t < fine.mesh.triangles.size(); ++t) {
    const std::int32_t coarse = fine.parent[t];
    const std::int64_t id = part.patch.triangle_id[coarse];
    for (const std::int32_t v : fine.mesh.triangles[t])
      if (id < smallest[v]) {
        smallest[v] = id;
        owner[v] = part.triangle_owner[coarse];
      }
  }
  return owner;
}

struct IdRequest {
  std::int64_t input_id;
  std::int32_t requester;
};
struct IdAnswer {
  std::int64_t input_id;
  std::int32_t global_id;
};

/// The global ids of `wanted` (input ids of other ranks' vertices, with their owners), asked of
/// their owners, which know theirs from `owned` (input id -> global id, sorted). Collective.
std::vector<std::int32_t>
ask_global_ids(const par::Comm& comm, const std::vector<std::int64_t>& wanted,
               const std::vector<std::int32_t>& wanted_owner,
               const std::vector<std::pair<std::int64_t, std::int32_t>>& owned) {
  std::vector<std::vector<IdRequest>> requests(static_cast<std::size_t>(comm.size));
  for (std::size_t k = 0; k < wanted.size(); ++k)
    requests[wanted_owner[k]].push_back({wanted[k], comm.rank});
  std::vector<std::vector<IdAnswer>> answers(static_cast<std::size_t>(comm.size));
  for (const auto& request : par::exchange_records(comm, requests)) {
    const auto it =
        std::lower_bound(owned.begin(), owned.end(), std::pair{request.input_id, std::int32_t{-1}});
    TEXSIM_VERIFY(it != owned.end() && it->first == request.input_id,
                  "DistributedMesh: rank " << comm.rank << " was asked for vertex "
                                           << request.input_id << ", which it does not own");
    answers[request.requester].push_back({request.input_id, it->second});
  }
  auto received = par::exchange_records(comm, answers);
  std::sort(received.begin(), received.end(),
            [](const IdAnswer& a, const IdAnswer& b) { return a.input_id < b.input_id; });
  std::vector<std::int32_t> global(wanted.size());
  for (std::size_t k = 0; k < wanted.size(); ++k) {
    const auto it =
        std::lower_bound(received.begin(), received.end(), wanted[k],
                         [](const IdAnswer& a, std::int64_t id) { return a.input_id < id; });
    TEXSIM_VERIFY(it != received.end() && it->input_id == wanted[k],
                  "DistributedMesh: no answer for vertex " << wanted[k]);
    global[k] = it->global_id;
  }
  return global;
}

} // namespace

DistributedMesh::DistributedMesh(const par::Comm& comm, const TriangleMesh& root_mesh,
                                 PartitionMethod method, std::span<const RefinementStep> refinement,
                                 std::span<const char> root_creases)
    : comm_(comm), rank_(comm.rank), topology_(TriangleMesh{}) {
  const double start_s = wall_seconds();
  const int rings = coarse_halo_rings(int(refinement.size()));
  std::unique_ptr<CoarsePartition> root;
  par::run_collectively(comm, [&] {
    if (comm.is_root())
      root = std::make_unique<CoarsePartition>(root_mesh, root_creases, method, comm.size, rings);
  });
  std::int64_t coarse_triangles = root ? root->triangle_count() : 0;
  MPI_Bcast(&coarse_triangles, 1, MPI_INT64_T, 0, comm.raw);
  global_triangles_ = coarse_triangles << (2 * refinement.size());
  const CoarsePart part = scatter_parts(comm, std::move(root));
  if (comm.is_root())
    root_seconds_ = wall_seconds() - start_s;

  // Refine the part, keep the fine vertices this rank owns, in Morton order (neighbours close in
  // memory: ICC-preconditioned CG needs 23 iterations instead of 33 in input order on a level-7
  // icosphere), ties by input id.
  RefinedPatch fine = refine_patch(part.patch, refinement);
  const auto owner = fine_owners(part, fine);
  std::vector<std::int32_t> owned;
  std::vector<std::array<double, 3>> owned_points;
  for (std::int32_t v = 0; v < fine.mesh.num_vertices(); ++v)
    if (owner[v] == rank_) {
      owned.push_back(v);
      const auto& p = fine.mesh.positions[v];
      owned_points.push_back({p.x(), p.y(), p.z()});
    }
  const auto keys = par::morton_keys(owned_points);
  std::vector<std::size_t> order(owned.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(keys[a], fine.vertex_id[owned[a]]) <
           std::tie(keys[b], fine.vertex_id[owned[b]]);
  });
  std::vector<std::int32_t> sorted_owned(owned.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    sorted_owned[k] = owned[order[k]];
  owned = std::move(sorted_owned);

  const std::int32_t owned_total = std::int32_t(owned.size());
  std::vector<std::int32_t> counts(static_cast<std::size_t>(comm.size));
  MPI_Allgather(&owned_total, 1, MPI_INT32_T, counts.data(), 1, MPI_INT32_T, comm.raw);
  owner_begin_.assign(std::size_t(comm.size) + 1, 0);
  std::partial_sum(counts.begin(), counts.end(), owner_begin_.begin() + 1);

  // The halo, ring by ring: the triangles touching the previous ring's vertices, and their new
  // vertices (the first ring's are the ghosts).
  const MeshTopology fine_topology(fine.mesh);
  const std::int32_t unset = -1;
  std::vector<std::int32_t> local_of(fine.mesh.positions.size(), unset);
  std::vector<char> triangle_taken(fine.mesh.triangles.size(), 0);
  for (std::size_t k = 0; k < owned.size(); ++k)
    local_of[owned[k]] = std::int32_t(k);
  std::vector<std::int32_t> ring = owned, triangles, ghosts, outer;
  for (int level = 0; level < kHaloRings; ++level) {
    std::vector<std::int32_t> next;
    for (const std::int32_t v : ring)
      for (const std::int32_t t : fine_topology.vertex_triangles().row(v)) {
        if (triangle_taken[t])
          continue;
        triangle_taken[t] = 1;
        TEXSIM_VERIFY(part.triangle_ring[fine.parent[t]] < rings,
                      "DistributedMesh: the halo of rank " << rank_
                                                           << " reaches past its coarse rings");
        triangles.push_back(t);
        for (const std::int32_t w : fine.mesh.triangles[t])
          if (local_of[w] == unset) {
            local_of[w] = 0; // marked; numbered below
            next.push_back(w);
          }
      }
    auto& into = level == 0 ? ghosts : outer;
    into.insert(into.end(), next.begin(), next.end());
    ring = std::move(next);
  }

  // Global ids: the owned ones follow owned_begin; the others come from their owners.
  std::vector<std::pair<std::int64_t, std::int32_t>> owned_ids(owned.size());
  for (std::size_t k = 0; k < owned.size(); ++k)
    owned_ids[k] = {fine.vertex_id[owned[k]], owned_begin() + std::int32_t(k)};
  std::sort(owned_ids.begin(), owned_ids.end());
  std::vector<std::int64_t> wanted;
  std::vector<std::int32_t> wanted_owner;
  for (const auto* list : {&ghosts, &outer})
    for (const std::int32_t v : *list) {
      wanted.push_back(fine.vertex_id[v]);
      wanted_owner.push_back(owner[v]);
      TEXSIM_VERIFY(owner[v] >= 0 && owner[v] != rank_,
                    "DistributedMesh: halo vertex " << fine.vertex_id[v] << " has no other owner");
    }
  const auto halo_global = ask_global_ids(comm, wanted, wanted_owner, owned_ids);
  std::vector<std::int32_t> global_of(fine.mesh.positions.size(), unset);
  for (std::size_t k = 0; k < owned.size(); ++k)
    global_of[owned[k]] = owned_begin() + std::int32_t(k);
  for (std::size_t k = 0; k < wanted.size(); ++k)
    global_of[k < ghosts.size() ? ghosts[k] : outer[k - ghosts.size()]] = halo_global[k];
  const auto by_global = [&](std::int32_t a, std::int32_t b) {
    return global_of[a] < global_of[b];
  };
  std::sort(ghosts.begin(), ghosts.end(), by_global);
  std::sort(outer.begin(), outer.end(), by_global);

  ghost_count_ = std::int32_t(ghosts.size());
  for (const auto* list : {&owned, &ghosts, &outer})
    for (const std::int32_t v : *list) {
      local_of[v] = std::int32_t(global_id_.size());
      global_id_.push_back(global_of[v]);
      input_id_.push_back(fine.vertex_id[v]);
      mesh_.positions.push_back(fine.mesh.positions[v]);
    }
  // Triangles in the order of their sorted input ids: the same order on every rank that holds
  // them, so sums over a vertex's triangles do not depend on the partition.
  struct KeyedTriangle {
    std::array<std::int64_t, 3> sorted_ids;
    std::int32_t triangle;
  };
  std::vector<KeyedTriangle> keyed(triangles.size());
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    auto& ids = keyed[k].sorted_ids;
    for (int i = 0; i < 3; ++i)
      ids[i] = fine.vertex_id[fine.mesh.triangles[triangles[k]][i]];
    std::sort(ids.begin(), ids.end());
    keyed[k].triangle = triangles[k];
  }
  std::sort(keyed.begin(), keyed.end(), [](const KeyedTriangle& a, const KeyedTriangle& b) {
    return a.sorted_ids < b.sorted_ids;
  });
  std::vector<EdgeFlags> triangle_creases;
  for (const auto& [ids, t] : keyed) {
    const auto& tri = fine.mesh.triangles[t];
    mesh_.triangles.push_back({local_of[tri[0]], local_of[tri[1]], local_of[tri[2]]});
    if (!fine.triangle_edge_crease.empty())
      triangle_creases.push_back(fine.triangle_edge_crease[t]);
  }
  fine = {};
  topology_ = MeshTopology(mesh_);
  if (!triangle_creases.empty())
    creases_ = edge_flags(topology_, triangle_creases);

  const std::int32_t owned_local = owned_count();
  std::int64_t cut = 0;
  for (std::int32_t v = 0; v < owned_local; ++v)
    for (const std::int32_t w : topology_.vertex_neighbors().row(v))
      cut += w >= owned_local;
  for (std::int32_t t = 0; t < mesh_.num_triangles(); ++t) {
    const auto& tri = mesh_.triangles[t];
    if (std::min({tri[0], tri[1], tri[2]}) >= owned_local)
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
  std::int64_t cut_total = 0;
  MPI_Allreduce(&cut, &cut_total, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  quality_.edge_cut = cut_total / 2; // each cut edge is seen from both of its ranks
  const std::int64_t mine[2] = {ghost_count_, std::int64_t(global_id_.size()) - owned_local};
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
