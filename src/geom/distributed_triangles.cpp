#include "geom/distributed_triangles.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/morton_order.hpp"
#include "geom/random_surface_points.hpp"
#include "par/gather_to_root.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>
#include <utility>

namespace texsim::geom {
namespace {

Vec3 corner(const std::array<double, 9>& corners, int c) {
  return {corners[3 * c], corners[3 * c + 1], corners[3 * c + 2]};
}

/// The first triangle id of rank r's area slots (even runs of ids).
std::int64_t slot_begin(std::int64_t triangles, int rank, int ranks) {
  return par::even_run_begin(triangles, rank, ranks);
}

/// What the rank holding the whole mesh knows of it: each rank's share and area slots, and the
/// totals.
struct WholeMesh {
  const TriangleMesh& mesh;
  std::vector<EdgeFlags> creases; ///< per triangle; empty for none
  std::vector<int> part;
  std::vector<double> prefix;
  std::int64_t last_positive = -1;

  WholeMesh(const TriangleMesh& whole, std::span<const char> edge_creases, int ranks)
      : mesh(whole), part(morton_triangle_parts(whole, ranks)) {
    if (!edge_creases.empty())
      creases = triangle_edge_flags(MeshTopology(whole), edge_creases);
    // AreaSampler's sums: the same bits.
    auto sums = area_prefix_sums(whole);
    prefix = std::move(sums.sums);
    last_positive = sums.last_positive;
  }

  TriangleRecord record(std::size_t t) const {
    TriangleRecord r;
    r.id = std::int64_t(t);
    for (int c = 0; c < 3; ++c)
      r.vertex[c] = mesh.triangles[t][c];
    r.corners = corners_of(mesh, t);
    if (!creases.empty())
      r.creases = creases[t];
    return r;
  }

  /// The longest edge of the mesh, and the 90th percentile of the triangles' longest edges.
  std::pair<double, double> edge_lengths() const {
    std::vector<double> longest(mesh.triangles.size(), 0.0);
    for (std::size_t t = 0; t < longest.size(); ++t)
      for (int c = 0; c < 3; ++c)
        longest[t] = std::max(longest[t], (mesh.positions[mesh.triangles[t][c]] -
                                           mesh.positions[mesh.triangles[t][(c + 1) % 3]])
                                              .norm());
    if (longest.empty())
      return {0.0, 0.0};
    const double max = *std::max_element(longest.begin(), longest.end());
    const auto tenth = longest.begin() + std::ptrdiff_t(longest.size() * 9 / 10);
    std::nth_element(longest.begin(), tenth, longest.end());
    return {max, *tenth};
  }
};

} // namespace

std::array<double, 9> corners_of(const TriangleMesh& mesh, std::size_t t) {
  std::array<double, 9> corners{};
  for (int c = 0; c < 3; ++c)
    for (int axis = 0; axis < 3; ++axis)
      corners[3 * c + axis] = mesh.positions[mesh.triangles[t][c]][axis];
  return corners;
}

std::int32_t LocalSurface::local_triangle(std::int64_t id) const {
  const auto it = std::lower_bound(triangle_ids.begin(), triangle_ids.end(), id);
  return it != triangle_ids.end() && *it == id ? std::int32_t(it - triangle_ids.begin()) : -1;
}

LocalSurface LocalSurface::from_records(std::vector<TriangleRecord> records) {
  std::sort(records.begin(), records.end(),
            [](const TriangleRecord& a, const TriangleRecord& b) { return a.id < b.id; });
  std::vector<std::int64_t> ids;
  std::vector<std::array<std::int64_t, 3>> corners;
  std::vector<EdgeFlags> creases;
  for (const auto& r : records) {
    ids.push_back(r.id);
    corners.push_back(r.vertex);
    creases.push_back(r.creases);
  }
  return assemble(std::move(ids), corners, std::move(creases),
                  [&](std::size_t k, int c) { return corner(records[k].corners, c); });
}

LocalSurface LocalSurface::assemble(std::vector<std::int64_t> ids,
                                    std::span<const std::array<std::int64_t, 3>> corners,
                                    std::vector<EdgeFlags> creases,
                                    const std::function<Vec3(std::size_t, int)>& corner_position) {
  LocalSurface local;
  for (const auto& triangle : corners)
    local.vertex_ids.insert(local.vertex_ids.end(), triangle.begin(), triangle.end());
  std::sort(local.vertex_ids.begin(), local.vertex_ids.end());
  local.vertex_ids.erase(std::unique(local.vertex_ids.begin(), local.vertex_ids.end()),
                         local.vertex_ids.end());
  local.vertex_ids.shrink_to_fit();
  local.mesh.positions.resize(local.vertex_ids.size());
  local.mesh.triangles.reserve(corners.size());
  for (std::size_t k = 0; k < corners.size(); ++k) {
    TEXSIM_VERIFY(k == 0 || ids[k - 1] < ids[k],
                  "LocalSurface: triangle " << ids[k] << " given twice or out of order");
    Triangle triangle{};
    for (int c = 0; c < 3; ++c) {
      triangle[c] = std::int32_t(
          std::lower_bound(local.vertex_ids.begin(), local.vertex_ids.end(), corners[k][c]) -
          local.vertex_ids.begin());
      local.mesh.positions[std::size_t(triangle[c])] = corner_position(k, c);
    }
    local.mesh.triangles.push_back(triangle);
  }
  local.triangle_ids = std::move(ids);
  local.triangle_creases = std::move(creases);
  return local;
}

TriangleRecord DistributedTriangles::owned_record(std::size_t k) const {
  TriangleRecord r;
  r.id = share_.triangle_ids[k];
  for (int c = 0; c < 3; ++c) {
    const auto local = std::size_t(share_.mesh.triangles[k][c]);
    r.vertex[c] = share_.vertex_ids[local];
    for (int axis = 0; axis < 3; ++axis)
      r.corners[3 * c + axis] = share_.mesh.positions[local][axis];
  }
  r.creases = share_.triangle_creases[k];
  return r;
}

DistributedTriangles DistributedTriangles::from_root(const par::Comm& comm,
                                                     const TriangleMesh& root_mesh,
                                                     std::span<const char> root_creases,
                                                     Sampling sampling) {
  DistributedTriangles split;
  std::array<std::int64_t, 2> counts{};
  // count, last positive; total area, longest edge, bounds (6), each rank's last prefix sum, the
  // sampling spacing
  std::vector<double> values(9 + std::size_t(comm.size));
  std::optional<WholeMesh> whole;
  std::vector<std::vector<std::int32_t>> members(comm.size); // each rank's triangles, on rank 0
  const auto triangles = std::int64_t(root_mesh.triangles.size());
  if (comm.is_root()) {
    whole.emplace(root_mesh, root_creases, comm.size);
    for (std::size_t t = 0; t < whole->part.size(); ++t)
      members[whole->part[t]].push_back(std::int32_t(t));
    for (int r = 0; r < comm.size; ++r) {
      const std::int64_t begin = slot_begin(triangles, r, comm.size);
      const std::int64_t end = slot_begin(triangles, r + 1, comm.size);
      values[8 + r] =
          end > begin ? whole->prefix[end - 1] : -std::numeric_limits<double>::infinity();
    }
    counts = {triangles, whole->last_positive};
    const Box3 bounds = Box3::around(root_mesh.positions);
    values[0] = whole->prefix.empty() ? 0.0 : whole->prefix.back();
    std::tie(values[1], values[8 + comm.size]) = whole->edge_lengths();
    for (int axis = 0; axis < 3; ++axis) {
      values[2 + axis] = bounds.lo[axis];
      values[5 + axis] = bounds.hi[axis];
    }
  }
  // Rank 0 makes one rank's records (or slots) at a time and sends them before making the next:
  // all ranks' records at once were 112 bytes a triangle of the whole mesh on rank 0. Its own
  // share it takes straight from the mesh.
  auto received = par::scatter_from_root<TriangleRecord>(comm, [&](int r) {
    std::vector<TriangleRecord> part;
    if (r == comm.rank)
      return part;
    part.reserve(members[r].size());
    for (const std::int32_t t : members[r])
      part.push_back(whole->record(std::size_t(t)));
    return part;
  });
  if (comm.is_root()) {
    const std::vector<std::int32_t>& own = members[comm.rank];
    std::vector<std::int64_t> ids(own.begin(), own.end());
    std::vector<std::array<std::int64_t, 3>> corners;
    std::vector<EdgeFlags> creases;
    for (const std::int32_t t : own) {
      const Triangle& c = root_mesh.triangles[std::size_t(t)];
      corners.push_back({c[0], c[1], c[2]});
      creases.push_back(whole->creases.empty() ? EdgeFlags{} : whole->creases[std::size_t(t)]);
    }
    split.share_ = LocalSurface::assemble(
        std::move(ids), corners, std::move(creases), [&](std::size_t k, int c) {
          return root_mesh.positions[std::size_t(root_mesh.triangles[std::size_t(own[k])][c])];
        });
  } else {
    split.share_ = LocalSurface::from_records(std::move(received));
  }
  split.sampling_ = sampling == Sampling::area;
  if (split.sampling_)
    split.slots_ = par::scatter_from_root<AreaSlot>(comm, [&](int r) {
      std::vector<AreaSlot> part;
      for (std::int64_t t = slot_begin(triangles, r, comm.size);
           t < slot_begin(triangles, r + 1, comm.size); ++t)
        part.push_back({whole->prefix[t], corners_of(root_mesh, std::size_t(t))});
      return part;
    });
  MPI_Bcast(counts.data(), 2, MPI_INT64_T, 0, comm.raw);
  MPI_Bcast(values.data(), int(values.size()), MPI_DOUBLE, 0, comm.raw);
  split.global_count_ = counts[0];
  split.last_positive_ = counts[1];
  split.total_area_ = values[0];
  split.longest_edge_ = values[1];
  for (int axis = 0; axis < 3; ++axis) {
    split.bounds_.lo[axis] = values[2 + axis];
    split.bounds_.hi[axis] = values[5 + axis];
  }
  split.slots_begin_ = slot_begin(split.global_count_, comm.rank, comm.size);
  split.slot_last_.assign(values.begin() + 8, values.begin() + 8 + comm.size);
  split.sample_spacing_ = values[8 + comm.size];
  return split;
}

DistributedTriangles DistributedTriangles::from_replicated(const par::Comm& comm,
                                                           const TriangleMesh& mesh) {
  // Every rank knows the whole mesh: each takes its own share, with no messages.
  DistributedTriangles split;
  const WholeMesh whole(mesh, {}, comm.size);
  std::vector<TriangleRecord> owned;
  for (std::size_t t = 0; t < whole.part.size(); ++t)
    if (whole.part[t] == comm.rank)
      owned.push_back(whole.record(t));
  split.share_ = LocalSurface::from_records(std::move(owned));
  split.sampling_ = true;
  split.global_count_ = std::int64_t(mesh.triangles.size());
  split.last_positive_ = whole.last_positive;
  split.total_area_ = whole.prefix.empty() ? 0.0 : whole.prefix.back();
  std::tie(split.longest_edge_, split.sample_spacing_) = whole.edge_lengths();
  split.bounds_ = Box3::around(mesh.positions);
  split.slots_begin_ = slot_begin(split.global_count_, comm.rank, comm.size);
  const std::int64_t slots_end = slot_begin(split.global_count_, comm.rank + 1, comm.size);
  for (std::int64_t t = split.slots_begin_; t < slots_end; ++t)
    split.slots_.push_back({whole.prefix[t], corners_of(mesh, std::size_t(t))});
  for (int r = 0; r < comm.size; ++r) {
    const std::int64_t begin = slot_begin(split.global_count_, r, comm.size);
    const std::int64_t end = slot_begin(split.global_count_, r + 1, comm.size);
    split.slot_last_.push_back(end > begin ? whole.prefix[end - 1]
                                           : -std::numeric_limits<double>::infinity());
  }
  return split;
}

LocalSurface DistributedTriangles::window(const par::Comm& comm, std::span<const Vec3> positions,
                                          double reach) const {
  // A triangle with a point within `reach` of p has a sample within reach + h of p (below).
  const double grown = reach + sample_spacing_;
  // Cells of the grown distance: larger ones make boxes that reach across thin parts and take
  // far more triangles than the points can walk to.
  return sampled_window(comm, covering_boxes(positions, grown, grown));
}

LocalSurface DistributedTriangles::window(const par::Comm& comm,
                                          std::span<const Box3> boxes) const {
  // A triangle with a point inside a box has a sample within h of it (below).
  std::vector<Box3> grown;
  grown.reserve(boxes.size());
  for (const Box3& box : boxes)
    grown.push_back(box.expanded(sample_spacing_));
  return sampled_window(comm, grown);
}

LocalSurface DistributedTriangles::sampled_window(const par::Comm& comm,
                                                  std::span<const Box3> boxes) const {
  // Each triangle stands for points that come within the sampling spacing h of all of its
  // points: its centroid when its longest edge is at most h, else the corners of its split into
  // n^2 similar triangles of edges at most h (a long sliver of a raw scan, which one generous
  // bound for all would make every window the whole mesh). A triangle with a point within
  // `reach` of p then has a sample within reach + h of p, and one with a point inside a box has
  // a sample inside the box grown by h: the other ranks send the triangles of the samples in
  // the boxes.
  std::vector<std::int64_t> sample_ids;
  std::vector<Vec3> samples;
  std::vector<std::int32_t> sample_triangle;
  const TriangleMesh& share = share_.mesh;
  for (std::size_t k = 0; k < share.triangles.size(); ++k) {
    const Vec3& a = share.positions[std::size_t(share.triangles[k][0])];
    const Vec3& b = share.positions[std::size_t(share.triangles[k][1])];
    const Vec3& c = share.positions[std::size_t(share.triangles[k][2])];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const auto add = [&](const Vec3& sample) {
      sample_ids.push_back(std::int64_t(sample_ids.size()) * comm.size + comm.rank); // unique
      samples.push_back(sample);
      sample_triangle.push_back(std::int32_t(k));
    };
    if (!(longest > sample_spacing_)) {
      add((a + b + c) / 3.0);
      continue;
    }
    const int n = int(std::ceil(longest / sample_spacing_));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        add(a + (double(i) / n) * (b - a) + (double(j) / n) * (c - a));
  }
  const auto near = exchange_point_halo(comm, sample_ids, samples, boxes);
  struct Request {
    std::int32_t requester;
    std::int32_t sample;
  };
  std::vector<std::vector<Request>> requests(comm.size);
  for (const auto& h : near)
    requests[h.owner].push_back({comm.rank, h.owner_index});
  // Several samples of one triangle may ask for it: each requester gets it once.
  std::vector<std::pair<std::int32_t, std::int32_t>> asked;
  for (const auto& q : par::exchange_records(comm, requests))
    asked.emplace_back(q.requester, sample_triangle[std::size_t(q.sample)]);
  std::sort(asked.begin(), asked.end());
  asked.erase(std::unique(asked.begin(), asked.end()), asked.end());
  std::vector<std::vector<TriangleRecord>> replies(comm.size);
  for (const auto& [requester, k] : asked)
    replies[requester].push_back(owned_record(std::size_t(k)));
  auto records = par::exchange_records(comm, replies);
  // This rank's own triangles by the same test.
  const auto inside = inside_boxes(samples, boxes);
  std::vector<char> taken(owned_count(), 0);
  for (std::size_t k = 0; k < samples.size(); ++k)
    taken[std::size_t(sample_triangle[k])] |= inside[k];
  for (std::size_t k = 0; k < taken.size(); ++k)
    if (taken[k])
      records.push_back(owned_record(k));
  return LocalSurface::from_records(std::move(records));
}

DistributedSurfacePoints DistributedTriangles::random_points(const par::Comm& comm,
                                                             std::int64_t first_id,
                                                             std::int64_t count,
                                                             std::uint64_t seed) const {
  TEXSIM_VERIFY(sampling_, "DistributedTriangles::random_points on a split without area slots");
  TEXSIM_VERIFY(last_positive_ >= 0 && total_area_ > 0.0,
                "AreaSampler: the mesh has no triangle of positive area (" << global_count_
                                                                           << " triangles)");
  const CounterRng rng(seed, kRandomSurfacePointStream);
  // Rank r's slots end with the prefix sum slot_last[r]; ranks without slots repeat the one
  // before, so the first rank whose last sum exceeds u * total holds the triangle AreaSampler
  // picks. u * total may round up to the total itself: the last triangle of positive area
  // takes that case, as there.
  std::vector<double> last = slot_last_;
  for (std::size_t r = 1; r < last.size(); ++r)
    last[r] = std::max(last[r], last[r - 1]);
  int fallback = 0;
  while (slot_begin(global_count_, fallback + 1, comm.size) <= last_positive_)
    ++fallback;
  const auto holder = [&](double target) {
    const auto it = std::upper_bound(last.begin(), last.end(), target);
    return it == last.end() ? fallback : int(it - last.begin());
  };
  std::vector<std::vector<std::int64_t>> asks(comm.size);
  for (std::int64_t id = first_id; id < first_id + count; ++id)
    asks[holder(rng.uniform(std::uint64_t(id), 0, 0) * total_area_)].push_back(id);

  DistributedSurfacePoints placed;
  for (const std::int64_t id : par::exchange_records(comm, asks)) {
    const double target = rng.uniform(std::uint64_t(id), 0, 0) * total_area_;
    std::int64_t t = last_positive_;
    if (!slots_.empty() && slots_.back().prefix > target)
      t = slots_begin_ +
          (std::upper_bound(slots_.begin(), slots_.end(), target,
                            [](double v, const AreaSlot& s) { return v < s.prefix; }) -
           slots_.begin());
    const AreaSlot& slot = slots_[std::size_t(t - slots_begin_)];
    // AreaSampler::sample's arithmetic, term for term.
    const double s = std::sqrt(rng.uniform(std::uint64_t(id), 0, 1));
    const double v = rng.uniform(std::uint64_t(id), 0, 2);
    SurfacePoint point;
    point.position = (1.0 - s) * corner(slot.corners, 0) +
                     (s * (1.0 - v)) * corner(slot.corners, 1) + (s * v) * corner(slot.corners, 2);
    point.triangle = std::int32_t(t);
    placed.ids.push_back(id);
    placed.points.push_back(point);
  }
  return placed;
}

} // namespace texsim::geom
