#include "geom/point_relaxation.hpp"

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/rng.hpp"
#include "geom/morton_order.hpp"
#include "geom/surface_window.hpp"

#include <mpi.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <tuple>
#include <utility>

namespace texsim::geom {
namespace {

/// CounterRng stream for the separation direction of coincident points.
constexpr std::uint32_t kCoincidentPointStream = 0x5402;

/// Cell edge of the halo's covering boxes, in repulsion radii: smaller cells follow a rank's
/// points more closely (fewer halo points) but make more boxes to allgather.
constexpr double kHaloCellFactor = 3.0;

/// Uniform hash grid over a point set: cells of a given size hashed into about two buckets per
/// point. Each bucket stores its points contiguously (cell key, position, index) in increasing
/// index order, so a cell's points are read from one run of memory, hash collisions are filtered
/// by the key and no cell is visited twice.
class PointGrid {
public:
  struct Slot {
    std::uint64_t key;
    Vec3 position;
    std::uint32_t index; ///< index in the span the grid was built from
    std::int32_t label;  ///< caller's label of the point (-1 when none was given)
  };

  PointGrid(std::span<const Vec3> points, double cell, std::span<const std::int32_t> labels = {}) {
    const Box3 box = Box3::around(points);
    origin_ = box.empty() ? Vec3::Zero() : box.lo;
    const double extent = box.empty() ? 0.0 : (box.hi - box.lo).maxCoeff();
    // At most 2^20 cells per axis so that keys fit in 21 bits per axis with room for rings.
    cell_ = std::max({cell, extent / double(1 << 20), std::numeric_limits<double>::min()});
    std::size_t buckets = 16;
    while (buckets < 2 * points.size())
      buckets *= 2;
    shift_ = 64 - std::countr_zero(buckets);
    offsets_.assign(buckets + 1, 0);
    std::vector<std::uint64_t> key(points.size());
    std::vector<std::uint32_t> bucket(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto c = cell_of(points[i]);
      key[i] = pack(c[0], c[1], c[2]);
      bucket[i] = bucket_of(key[i]);
      ++offsets_[bucket[i] + 1];
    }
    for (std::size_t b = 0; b < buckets; ++b)
      offsets_[b + 1] += offsets_[b];
    slots_.resize(points.size());
    std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (std::size_t i = 0; i < points.size(); ++i)
      slots_[fill[bucket[i]]++] = {key[i], points[i], static_cast<std::uint32_t>(i),
                                   labels.empty() ? -1 : labels[i]};
  }

  double cell() const { return cell_; }
  std::size_t num_buckets() const { return offsets_.size() - 1; }
  /// The points hashed to bucket b (one or more cells).
  std::span<const Slot> bucket(std::size_t b) const {
    return {slots_.data() + offsets_[b], slots_.data() + offsets_[b + 1]};
  }

  /// Calls visit(slot) for every point in the cells within `rings` cells of p's cell.
  template <class Visit> void for_each_near(const Vec3& p, int rings, Visit&& visit) const {
    for_each_near_cell(cell_of(p), rings, visit);
  }

  /// The same around the cell with key `key`.
  template <class Visit> void for_each_near_key(std::uint64_t key, int rings, Visit&& visit) const {
    const std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
    for_each_near_cell(
        {std::int64_t(key & mask), std::int64_t(key >> 21 & mask), std::int64_t(key >> 42 & mask)},
        rings, visit);
  }

private:
  static constexpr std::int64_t kMaxCell = (std::int64_t{1} << 21) - 1;

  template <class Visit>
  void for_each_near_cell(const std::array<std::int64_t, 3>& c, int rings, Visit& visit) const {
    for (int dz = -rings; dz <= rings; ++dz)
      for (int dy = -rings; dy <= rings; ++dy)
        for (int dx = -rings; dx <= rings; ++dx) {
          const std::int64_t x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
          if (x < 0 || y < 0 || z < 0 || x > kMaxCell || y > kMaxCell || z > kMaxCell)
            continue;
          const std::uint64_t key = pack(x, y, z);
          const std::uint32_t b = bucket_of(key);
          for (std::uint32_t s = offsets_[b]; s < offsets_[b + 1]; ++s)
            if (slots_[s].key == key)
              visit(slots_[s]);
        }
  }

  std::array<std::int64_t, 3> cell_of(const Vec3& p) const {
    std::array<std::int64_t, 3> c;
    for (int axis = 0; axis < 3; ++axis) {
      const double f = std::floor((p[axis] - origin_[axis]) / cell_);
      c[axis] = static_cast<std::int64_t>(std::clamp(f, 0.0, double(kMaxCell)));
    }
    return c;
  }
  static std::uint64_t pack(std::int64_t x, std::int64_t y, std::int64_t z) {
    return std::uint64_t(x) | std::uint64_t(y) << 21 | std::uint64_t(z) << 42;
  }
  // The eight cells of a 2 x 2 x 2 block get consecutive buckets, so that walking the buckets in
  // order visits neighbouring cells one after the other (their neighbourhoods overlap in cache).
  std::uint32_t bucket_of(std::uint64_t key) const {
    const std::uint64_t block = (key >> 1) & kBlockMask;
    const std::uint64_t corner = (key & 1) | (key >> 20 & 2) | (key >> 40 & 4);
    return static_cast<std::uint32_t>(((block * 0x9E3779B97F4A7C15ULL) >> (shift_ + 3)) << 3 |
                                      corner);
  }
  // Clears the lowest bit of each axis' 21 (after the shift by one: bits 20, 41, 62 are stale).
  static constexpr std::uint64_t kBlockMask =
      ~((std::uint64_t{1} << 20) | (std::uint64_t{1} << 41) | (std::uint64_t{1} << 62));

  Vec3 origin_;
  double cell_ = 1.0;
  int shift_ = 60;
  std::vector<std::uint32_t> offsets_;
  std::vector<Slot> slots_;
};

Vec3 coincident_repulsion(std::int64_t p_id, std::int64_t q_id, double radius) {
  // Coincident points would feel the same forces forever: split them along a direction drawn
  // from the id pair, the larger id taking the positive sense.
  const CounterRng rng(0, kCoincidentPointStream);
  const auto low = static_cast<std::uint64_t>(std::min(p_id, q_id));
  const auto high = static_cast<std::uint32_t>(std::max(p_id, q_id));
  Vec3 direction(rng.normal(low, high, 0), rng.normal(low, high, 1), rng.normal(low, high, 2));
  direction.normalize();
  return (p_id > q_id ? radius : -radius) * direction;
}

double max_over_ranks(const par::Comm& comm, double value) {
  double result = value;
  MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, MPI_MAX, comm.raw);
  return result;
}

} // namespace

double repulsion_radius(double area, std::int64_t count, double radius_factor) {
  TEXSIM_VERIFY(area > 0.0 && count > 0 && radius_factor > 0.0,
                "repulsion_radius: area " << area << ", count " << count << " and radius_factor "
                                          << radius_factor << " must be positive");
  return radius_factor * std::sqrt(area / double(count));
}

Vec3 repulsion(const Vec3& p, std::int64_t p_id, const Vec3& q, std::int64_t q_id, double radius) {
  const Vec3 away = p - q;
  const double d = away.norm();
  if (d >= radius)
    return Vec3::Zero();
  if (d > 1e-9 * radius)
    return away * ((radius - d) / d);
  return coincident_repulsion(p_id, q_id, radius);
}

Vec3 relaxation_move(const Vec3& force, double radius, const RelaxationSettings& settings) {
  const double neighbours = std::numbers::pi * settings.radius_factor * settings.radius_factor;
  Vec3 move = (settings.step / neighbours) * force;
  const double limit = settings.step * radius;
  const double length = move.norm();
  if (length > limit)
    move *= limit / length;
  return move;
}

std::vector<SurfacePoint> relaxation_sweep(const SurfaceWalker& walker,
                                           std::span<const std::int64_t> ids,
                                           std::span<const SurfacePoint> points,
                                           std::span<const HaloPoint> halo, double radius,
                                           const RelaxationSettings& settings, double* move_sum) {
  TEXSIM_VERIFY(ids.size() == points.size(),
                "relaxation_sweep: " << ids.size() << " ids but " << points.size() << " points");
  TEXSIM_VERIFY(radius > 0.0, "relaxation_sweep: radius " << radius << " must be positive");
  TEXSIM_VERIFY(std::is_sorted(ids.begin(), ids.end()), "relaxation_sweep: ids must increase");
  TEXSIM_VERIFY(std::is_sorted(halo.begin(), halo.end(),
                               [](const HaloPoint& a, const HaloPoint& b) { return a.id < b.id; }),
                "relaxation_sweep: halo points must be sorted by id");
  TEXSIM_VERIFY(points.size() + halo.size() < (std::size_t{1} << 31),
                "relaxation_sweep: too many points for one rank");
  // All points of this sweep, owned and halo, merged in increasing id order: a point's index is
  // its rank by id, so neighbours are sorted by id by sorting indices.
  const std::size_t owned = points.size();
  const std::size_t total = owned + halo.size();
  std::vector<Vec3> positions(total);
  std::vector<std::int64_t> merged_ids(total);
  std::vector<std::int32_t> owned_of(total, -1); // owned index of merged point, -1 for halo
  {
    std::size_t i = 0, h = 0;
    for (std::size_t m = 0; m < total; ++m) {
      if (h == halo.size() || (i < owned && ids[i] < halo[h].id)) {
        positions[m] = points[i].position;
        merged_ids[m] = ids[i];
        owned_of[m] = static_cast<std::int32_t>(i++);
      } else {
        positions[m] = halo[h].position;
        merged_ids[m] = halo[h++].id;
      }
    }
  }
  const PointGrid grid(positions, radius, owned_of);
  const double radius2 = radius * radius;
  std::vector<SurfacePoint> moved(owned);
  double total_move = 0.0;
  // Points of one grid cell share their candidate neighbours (the 27 cells around it), gathered
  // once per cell. Each point sums the forces of the candidates within the radius in increasing
  // id order, so the sum depends neither on the split into owned and halo points nor on the
  // thread count.
#pragma omp parallel reduction(+ : total_move)
  {
    struct Candidate {
      Vec3 position;
      std::uint32_t index;
    };
    std::vector<Candidate> candidates;
    std::vector<std::uint64_t> near; // merged index << 32 | candidate number
    std::vector<std::uint64_t> done_keys;
#pragma omp for schedule(dynamic, 64)
    for (std::size_t b = 0; b < grid.num_buckets(); ++b) {
      const auto bucket = grid.bucket(b);
      done_keys.clear();
      for (std::size_t first = 0; first < bucket.size(); ++first) {
        const std::uint64_t key = bucket[first].key;
        if (bucket[first].label < 0 ||
            std::find(done_keys.begin(), done_keys.end(), key) != done_keys.end())
          continue;
        done_keys.push_back(key);
        candidates.clear();
        grid.for_each_near_key(key, 1, [&](const PointGrid::Slot& q) {
          candidates.push_back({q.position, q.index});
        });
        for (std::size_t k = first; k < bucket.size(); ++k) {
          const std::uint32_t self = bucket[k].index;
          if (bucket[k].key != key || bucket[k].label < 0)
            continue;
          const Vec3& p = bucket[k].position;
          near.clear();
          for (std::uint32_t c = 0; c < candidates.size(); ++c)
            if ((candidates[c].position - p).squaredNorm() < radius2 && candidates[c].index != self)
              near.push_back(std::uint64_t(candidates[c].index) << 32 | c);
          // Insertion sort of a dozen keys.
          for (std::size_t m = 1; m < near.size(); ++m) {
            const std::uint64_t value = near[m];
            std::size_t l = m;
            for (; l > 0 && near[l - 1] > value; --l)
              near[l] = near[l - 1];
            near[l] = value;
          }
          Vec3 force = Vec3::Zero();
          // repulsion() inlined: d < radius holds for every entry.
          for (const std::uint64_t entry : near) {
            const Candidate& q = candidates[entry & 0xffffffffu];
            const Vec3 away = p - q.position;
            const double d = away.norm();
            if (d > 1e-9 * radius)
              force += away * ((radius - d) / d);
            else
              force += coincident_repulsion(merged_ids[self], merged_ids[q.index], radius);
          }
          const Vec3 move = relaxation_move(force, radius, settings);
          const std::size_t i = std::size_t(bucket[k].label);
          moved[i] = walker.move(points[i], move);
          total_move += move.norm();
        }
      }
    }
  }
  if (move_sum != nullptr)
    *move_sum = total_move;
  return moved;
}

DistributedSurfacePoints relaxed_surface_points(const par::Comm& comm,
                                                const DistributedTriangles& surface,
                                                std::int64_t count, std::uint64_t seed,
                                                const RelaxationSettings& settings,
                                                RelaxationReport* report) {
  TEXSIM_VERIFY(count > 0, "relaxed_surface_points: count " << count << " must be positive");
  TEXSIM_VERIFY(settings.iterations >= 0 && settings.radius_factor > 0.0 && settings.step > 0.0,
                "relaxed_surface_points: iterations "
                    << settings.iterations << ", radius_factor " << settings.radius_factor
                    << ", step " << settings.step
                    << ": iterations must not be negative, the others must be positive");
  const double setup_start = MPI_Wtime();
  const double radius = repulsion_radius(surface.total_area(), count, settings.radius_factor);

  // Each rank places the points of its share of the ids (point id -> the same point at any rank
  // count; the rank holding the triangle's area slot computes it), then the ranks sort them along
  // a Morton curve and each keeps an even run: spatially compact parts, and no rank ever holds
  // all points.
  const std::int64_t first = count * comm.rank / comm.size;
  const std::int64_t last = count * (comm.rank + 1) / comm.size;
  auto sorted = sort_along_morton_curve(comm, surface.bounds(),
                                        surface.random_points(comm, first, last - first, seed));
  // relaxation_sweep wants increasing ids.
  std::vector<std::size_t> by_id(sorted.ids.size());
  std::iota(by_id.begin(), by_id.end(), std::size_t{0});
  std::sort(by_id.begin(), by_id.end(),
            [&](std::size_t a, std::size_t b) { return sorted.ids[a] < sorted.ids[b]; });
  std::vector<std::int64_t> ids;
  std::vector<SurfacePoint> points;
  for (const std::size_t k : by_id) {
    ids.push_back(sorted.ids[k]);
    points.push_back(sorted.points[k]);
  }
  const double setup_seconds = MPI_Wtime() - setup_start;
  SurfaceWindow window(surface, settings.step * radius);

  std::vector<double> seconds(settings.iterations), mean_move(settings.iterations);
  std::int64_t max_halo = 0;
  std::vector<Vec3> positions(points.size());
  std::unique_ptr<Progress> progress;
  if (comm.rank == 0)
    progress = std::make_unique<Progress>("relaxing surface points", settings.iterations, "sweeps");
  for (int sweep = 0; sweep < settings.iterations; ++sweep) {
    const double start = MPI_Wtime();
    for (std::size_t i = 0; i < positions.size(); ++i)
      positions[i] = points[i].position;
    const auto halo = exchange_point_halo(
        comm, ids, positions, covering_boxes(positions, kHaloCellFactor * radius, radius));
    max_halo = std::max<std::int64_t>(max_halo, std::int64_t(halo.size()));
    double move_sum = 0.0;
    window.cover(comm, positions);
    points = window.to_global(relaxation_sweep(window.walker(), ids, window.to_local(points), halo,
                                               radius, settings, &move_sum));
    seconds[sweep] = MPI_Wtime() - start;
    mean_move[sweep] = move_sum;
    if (progress)
      progress->update(sweep + 1);
  }
  if (progress && settings.iterations > 0) {
    double elapsed = 0.0;
    for (double s : seconds)
      elapsed += s;
    if (elapsed > 5.0)
      progress->finish();
  }

  if (report != nullptr) {
    report->radius = radius;
    report->seconds_setup = max_over_ranks(comm, setup_seconds);
    report->seconds_per_iteration.assign(seconds.size(), 0.0);
    report->mean_move_per_iteration.assign(seconds.size(), 0.0);
    if (!seconds.empty()) {
      MPI_Allreduce(seconds.data(), report->seconds_per_iteration.data(), int(seconds.size()),
                    MPI_DOUBLE, MPI_MAX, comm.raw);
      MPI_Allreduce(mean_move.data(), report->mean_move_per_iteration.data(), int(mean_move.size()),
                    MPI_DOUBLE, MPI_SUM, comm.raw);
    }
    for (double& m : report->mean_move_per_iteration)
      m /= double(count) * radius;
    MPI_Allreduce(&max_halo, &report->max_halo_points, 1, MPI_INT64_T, MPI_MAX, comm.raw);
    report->window_fetches = window.fetches(); // the same on every rank: fetched together
    const std::int64_t held = window.triangles_max();
    MPI_Allreduce(&held, &report->window_triangles_max, 1, MPI_INT64_T, MPI_MAX, comm.raw);
  }
  DistributedSurfacePoints result;
  result.ids = std::move(ids);
  result.points = std::move(points);
  return result;
}

NeighborSpacing nearest_neighbor_spacing(std::span<const Vec3> positions) {
  const std::size_t n = positions.size();
  TEXSIM_VERIFY(n >= 2, "nearest_neighbor_spacing: needs at least two points, got " << n);
  // A cell of about the spacing of n points spread over the bounding box's surface; the search
  // widens ring by ring until the nearest point found is provably the nearest.
  const Box3 box = Box3::around(positions);
  const Vec3 extent = box.hi - box.lo;
  const double box_area =
      2.0 * (extent.x() * extent.y() + extent.y() * extent.z() + extent.z() * extent.x());
  double cell = std::sqrt(box_area / double(n));
  if (!(cell > 0.0))
    cell = std::max(extent.maxCoeff() / double(n), 1e-300);
  const PointGrid grid(positions, cell);
  std::vector<double> nearest(n);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    double best2 = std::numeric_limits<double>::infinity();
    for (int rings = 1;; ++rings) {
      if (rings > 8) {
        for (std::size_t j = 0; j < n; ++j)
          if (j != i)
            best2 = std::min(best2, (positions[j] - positions[i]).squaredNorm());
        break;
      }
      best2 = std::numeric_limits<double>::infinity();
      grid.for_each_near(positions[i], rings, [&](const PointGrid::Slot& q) {
        if (std::size_t(q.index) != i)
          best2 = std::min(best2, (q.position - positions[i]).squaredNorm());
      });
      // Every point within rings * cell of p lies in the visited cells.
      const double reach = rings * grid.cell();
      if (best2 <= reach * reach)
        break;
    }
    nearest[i] = std::sqrt(best2);
  }
  NeighborSpacing spacing;
  double sum = 0.0;
  spacing.min = nearest[0];
  spacing.max = nearest[0];
  for (double d : nearest) {
    sum += d;
    spacing.min = std::min(spacing.min, d);
    spacing.max = std::max(spacing.max, d);
  }
  spacing.mean = sum / double(n);
  double variance = 0.0;
  for (double d : nearest)
    variance += (d - spacing.mean) * (d - spacing.mean);
  variance /= double(n);
  spacing.cv = spacing.mean > 0.0 ? std::sqrt(variance) / spacing.mean : 0.0;
  return spacing;
}

} // namespace texsim::geom
