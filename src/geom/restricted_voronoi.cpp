#include "geom/restricted_voronoi.hpp"

#include "core/error.hpp"
#include "geom/point_kd_tree.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <iterator>
#include <limits>
#include <memory>
#include <sstream>

namespace texsim::geom {
namespace {

/// Neighbours kept per seed in the shared cache; a cell that needs more queries again, privately.
constexpr std::size_t kCachedNeighbours = 20;

/// nanoflann's squared distances and ours may differ by a few ulps: a returned seed is trusted to
/// belong to the nearest ones only when it is closer than the k-th distance by this relative
/// margin.
constexpr double kTrustMargin = 1e-12;

struct Neighbour {
  double distance2;
  std::int32_t seed;
};

// Written out so that the value (and the order it defines) is the same in every build and rank.
double squared_distance(const Vec3& a, const Vec3& b) {
  const double dx = a.x() - b.x();
  const double dy = a.y() - b.y();
  const double dz = a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

/// k-nearest seeds in the total order (squared distance, id, index).
class NeighbourFinder {
public:
  NeighbourFinder(std::span<const Vec3> seeds, std::span<const std::int64_t> ids)
      : seeds_(seeds), ids_(ids), cloud_{seeds},
        tree_(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(12)) {}

  std::span<const Vec3> seeds() const { return seeds_; }

  /// Seed a before seed b in the tie-break order (id, then index for equal ids).
  bool seed_before(std::int32_t a, std::int32_t b) const {
    return ids_[a] < ids_[b] || (ids_[a] == ids_[b] && a < b);
  }

  /// A prefix of all seeds but `exclude` sorted by (distance to `point`, id), from the k nearest:
  /// only those certainly closer than every seed not returned, so the prefix does not depend on
  /// k, on the tree, or on seeds farther away. Returns true when `out` holds every seed (but
  /// `exclude`).
  bool nearest(const Vec3& point, std::size_t k, std::int32_t exclude, std::vector<Neighbour>& out,
               std::vector<std::uint32_t>& index, std::vector<double>& distance2) const {
    k = std::min(k, seeds_.size());
    index.resize(k);
    distance2.resize(k);
    const std::size_t found = tree_.knnSearch(point.data(), k, index.data(), distance2.data());
    const bool complete = found == seeds_.size();
    const double limit = complete ? std::numeric_limits<double>::infinity()
                                  : distance2[found - 1] * (1.0 - kTrustMargin);
    out.clear();
    for (std::size_t r = 0; r < found; ++r) {
      const auto j = static_cast<std::int32_t>(index[r]);
      if (j == exclude)
        continue;
      const double d2 = squared_distance(point, seeds_[j]);
      if (d2 < limit)
        out.push_back({d2, j});
    }
    std::sort(out.begin(), out.end(), [this](const Neighbour& a, const Neighbour& b) {
      return a.distance2 < b.distance2 ||
             (a.distance2 == b.distance2 && seed_before(a.seed, b.seed));
    });
    return complete;
  }

private:
  std::span<const Vec3> seeds_;
  std::span<const std::int64_t> ids_;
  PointCloudView cloud_;
  PointKdTree tree_;
};

struct PolygonVertex {
  Vec3 point;
  std::int32_t label; ///< what made the edge from this vertex to the next: seed index, -1 = mesh
};

/// Per-thread scratch space, reused across triangles.
struct Workspace {
  explicit Workspace(std::size_t num_seeds) : visit_stamp(num_seeds, 0) {}
  std::vector<PolygonVertex> polygon, clipped;
  std::vector<double> side;
  std::vector<Neighbour> cached_copy, more, start;
  std::vector<std::uint32_t> knn_index;
  std::vector<double> knn_distance2;
  std::vector<std::uint32_t> visit_stamp; ///< per seed: the traversal that last visited it
  std::uint32_t stamp = 0;
  std::vector<std::int32_t> stack;
};

/// Each seed's first kCachedNeighbours neighbours, computed once by whichever thread needs them
/// first (seeds no piece touches are never queried, so a rank may pass more seeds than it needs).
class NeighbourCache {
public:
  explicit NeighbourCache(const NeighbourFinder& finder)
      : finder_(finder), size_(finder.seeds().size()), entries_(size_ * kCachedNeighbours),
        counts_(size_, 0), complete_(size_, 0),
        state_(std::make_unique<std::atomic<std::uint8_t>[]>(size_)) {}

  /// The known prefix of seed i's neighbours; `complete` tells whether it holds every other seed.
  std::span<const Neighbour> get(std::int32_t i, bool& complete, Workspace& ws) {
    std::uint8_t state = state_[i].load(std::memory_order_acquire);
    if (state != kReady) {
      std::uint8_t expected = kEmpty;
      if (state == kEmpty &&
          state_[i].compare_exchange_strong(expected, kFilling, std::memory_order_acquire)) {
        const bool all = query(i, ws.cached_copy, ws);
        std::copy(ws.cached_copy.begin(), ws.cached_copy.end(),
                  entries_.begin() + static_cast<std::ptrdiff_t>(i * kCachedNeighbours));
        counts_[i] = static_cast<std::uint32_t>(ws.cached_copy.size());
        complete_[i] = all ? 1 : 0;
        state_[i].store(kReady, std::memory_order_release);
      } else {
        // Another thread is filling it: the same list computed here costs less than waiting.
        complete = query(i, ws.cached_copy, ws);
        return ws.cached_copy;
      }
    }
    complete = complete_[i] != 0;
    return {entries_.data() + i * kCachedNeighbours, counts_[i]};
  }

private:
  static constexpr std::uint8_t kEmpty = 0, kFilling = 1, kReady = 2;

  bool query(std::int32_t i, std::vector<Neighbour>& out, Workspace& ws) const {
    bool all = finder_.nearest(finder_.seeds()[i], kCachedNeighbours + 1, i, out, ws.knn_index,
                               ws.knn_distance2);
    if (out.size() > kCachedNeighbours) { // coincident seeds pushed i itself out of the k nearest
      out.resize(kCachedNeighbours);
      all = false;
    }
    return all;
  }

  const NeighbourFinder& finder_;
  std::size_t size_;
  std::vector<Neighbour> entries_;
  std::vector<std::uint32_t> counts_;
  std::vector<std::uint8_t> complete_;
  std::unique_ptr<std::atomic<std::uint8_t>[]> state_;
};

enum class ClipResult { unchanged, cut, empty };

/// Sutherland-Hodgman clip of the convex polygon in ws.polygon by the half-space of points at least
/// as close to seed i as to seed j, labelling the new edge j. The plane's side function is
/// antisymmetric in (i, j) to the bit, so both cells see the same border.
ClipResult clip(const NeighbourFinder& finder, std::int32_t i, std::int32_t j, Workspace& ws) {
  const Vec3& si = finder.seeds()[i];
  const Vec3& sj = finder.seeds()[j];
  const Vec3 normal = sj - si;
  const Vec3 middle = 0.5 * (si + sj);
  std::vector<PolygonVertex>& polygon = ws.polygon;
  const std::size_t n = polygon.size();
  ws.side.resize(n);
  bool any_out = false, any_in = false;
  for (std::size_t k = 0; k < n; ++k) {
    const double f = (polygon[k].point - middle).dot(normal);
    ws.side[k] = f;
    any_out = any_out || f > 0.0;
    any_in = any_in || f < 0.0;
  }
  if (!any_out) {
    // Every vertex on the bisector: the piece lies in it (coincident seeds, or a flat piece
    // between mirror seeds); the smaller id takes it.
    if (!any_in && finder.seed_before(j, i))
      return ClipResult::empty;
    return ClipResult::unchanged; // exactly unchanged, so far seeds never alter a piece
  }
  if (!any_in)
    return ClipResult::empty; // at most a vertex or an edge is left

  std::vector<PolygonVertex>& out = ws.clipped;
  out.clear();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t next = k + 1 == n ? 0 : k + 1;
    const Vec3& a = polygon[k].point;
    const Vec3& b = polygon[next].point;
    const double fa = ws.side[k];
    const double fb = ws.side[next];
    if (fa <= 0.0) {
      if (fb > 0.0 && fa < 0.0) {
        out.push_back({a, polygon[k].label});
        out.push_back({a + (fa / (fa - fb)) * (b - a), j}); // leaves: the border with j starts
      } else {
        out.push_back({a, fb > 0.0 ? j : polygon[k].label});
      }
    } else if (fb < 0.0) {
      out.push_back({a + (fa / (fa - fb)) * (b - a), polygon[k].label}); // comes back in
    }
  }
  if (out.size() < 3)
    return ClipResult::empty;
  std::swap(ws.polygon, ws.clipped);
  return ClipResult::cut;
}

double max_distance2(const std::vector<PolygonVertex>& polygon, const Vec3& seed) {
  double r2 = 0.0;
  for (const PolygonVertex& v : polygon)
    r2 = std::max(r2, squared_distance(v.point, seed));
  return r2;
}

double polygon_area(const std::vector<PolygonVertex>& polygon) {
  Vec3 twice_area = Vec3::Zero();
  const Vec3& origin = polygon[0].point;
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
    twice_area += (polygon[k].point - origin).cross(polygon[k + 1].point - origin);
  return 0.5 * twice_area.norm();
}

class RvdBuilder {
public:
  RvdBuilder(const TriangleMesh& mesh, std::span<const Vec3> seeds,
             std::span<const std::int64_t> seed_ids, bool keep_polygons)
      : mesh_(mesh), finder_(seeds, seed_ids), cache_(finder_), keep_polygons_(keep_polygons) {}

  /// The pieces of triangle t, sorted by seed id.
  std::vector<VoronoiPiece> triangle_pieces(std::int32_t t, Workspace& ws) {
    const Triangle& tri = mesh_.triangles[t];
    const std::array<Vec3, 3> corners = {mesh_.positions[tri[0]], mesh_.positions[tri[1]],
                                         mesh_.positions[tri[2]]};
    std::vector<VoronoiPiece> pieces;
    std::array<std::int32_t, 1> start = {nearest_seed(corners[0], ws)};
    traverse(t, corners, start, ws, pieces);
    const double area = 0.5 * (corners[1] - corners[0]).cross(corners[2] - corners[0]).norm();
    if (!covers(pieces, corners, area)) {
      // Only when the first corner's cell meets t in a point or a segment (a corner equidistant
      // from several seeds): start as well from the other corners' and the centroid's cells.
      const std::array<std::int32_t, 4> starts = {
          start[0], nearest_seed(corners[1], ws), nearest_seed(corners[2], ws),
          nearest_seed((corners[0] + corners[1] + corners[2]) / 3.0, ws)};
      pieces.clear();
      traverse(t, corners, starts, ws, pieces);
      double covered = 0.0;
      for (const VoronoiPiece& piece : pieces)
        covered += piece.area;
      TEXSIM_VERIFY(covers(pieces, corners, area), "restricted Voronoi: the pieces of triangle "
                                                       << t << " cover " << covered
                                                       << " of its area " << area);
    }
    std::sort(pieces.begin(), pieces.end(), [this](const VoronoiPiece& a, const VoronoiPiece& b) {
      return finder_.seed_before(a.seed, b.seed);
    });
    return pieces;
  }

private:
  std::int32_t nearest_seed(const Vec3& point, Workspace& ws) const {
    for (std::size_t k = 4;; k *= 2) {
      finder_.nearest(point, k, -1, ws.start, ws.knn_index, ws.knn_distance2);
      if (!ws.start.empty())
        return ws.start.front().seed;
    }
  }

  static bool covers(const std::vector<VoronoiPiece>& pieces, const std::array<Vec3, 3>& corners,
                     double area) {
    double covered = 0.0;
    for (const VoronoiPiece& piece : pieces)
      covered += piece.area;
    double longest = 0.0, extent = 0.0;
    for (int k = 0; k < 3; ++k) {
      longest = std::max(longest, (corners[(k + 1) % 3] - corners[k]).norm());
      extent = std::max(extent, corners[k].cwiseAbs().maxCoeff());
    }
    // Round-off of the clipped vertices is relative to the coordinates, not to the area (slivers).
    return std::abs(covered - area) <= 1e-8 * area + 1e-12 * longest * (extent + longest);
  }

  /// Visits every cell meeting t, crossing from piece to piece through the bisector edges.
  void traverse(std::int32_t t, const std::array<Vec3, 3>& corners,
                std::span<const std::int32_t> starts, Workspace& ws,
                std::vector<VoronoiPiece>& pieces) {
    if (++ws.stamp == 0) { // wrapped around: forget every old visit
      std::fill(ws.visit_stamp.begin(), ws.visit_stamp.end(), 0u);
      ws.stamp = 1;
    }
    ws.stack.clear();
    for (const std::int32_t s : starts) {
      if (ws.visit_stamp[s] != ws.stamp) {
        ws.visit_stamp[s] = ws.stamp;
        ws.stack.push_back(s);
      }
    }
    while (!ws.stack.empty()) {
      const std::int32_t i = ws.stack.back();
      ws.stack.pop_back();
      std::int32_t emptied_by = -1;
      if (!clip_cell(t, corners, i, ws, emptied_by)) {
        // The seed whose half-space left nothing of i's piece: on a bisector shared by several
        // seeds (mirror seeds, say) the edge may be labelled by a seed whose piece is empty, and
        // the cell beyond it is this one.
        if (ws.visit_stamp[emptied_by] != ws.stamp) {
          ws.visit_stamp[emptied_by] = ws.stamp;
          ws.stack.push_back(emptied_by);
        }
        continue;
      }
      for (const PolygonVertex& v : ws.polygon) {
        if (v.label >= 0 && ws.visit_stamp[v.label] != ws.stamp) {
          ws.visit_stamp[v.label] = ws.stamp;
          ws.stack.push_back(v.label);
        }
      }
      const double area = polygon_area(ws.polygon);
      if (area > 0.0)
        pieces.push_back(make_piece(t, i, area, ws.polygon));
    }
  }

  /// Clips triangle t by the cell of seed i into ws.polygon; false when nothing is left, with the
  /// seed whose half-space removed the rest in `emptied_by`.
  bool clip_cell(std::int32_t t, const std::array<Vec3, 3>& corners, std::int32_t i, Workspace& ws,
                 std::int32_t& emptied_by) {
    ws.polygon.assign({{corners[0], -1}, {corners[1], -1}, {corners[2], -1}});
    const Vec3& seed = finder_.seeds()[i];
    double radius2 = max_distance2(ws.polygon, seed);
    bool complete = false;
    std::span<const Neighbour> neighbours = cache_.get(i, complete, ws);
    std::size_t used = 0;
    std::size_t k = kCachedNeighbours;
    for (;;) {
      if (used == neighbours.size()) {
        if (complete) {
          std::ostringstream message;
          message << "restricted Voronoi: the cell of seed " << i << " in triangle " << t
                  << " is not certified after all " << finder_.seeds().size()
                  << " given seeds (twice its radius, " << 2.0 * std::sqrt(radius2)
                  << ", reaches beyond the farthest seed): the halo of seeds is too small";
          throw Error(message.str());
        }
        // The same order continued: the first `used` entries are unchanged.
        k *= 2;
        complete = finder_.nearest(seed, k + 1, i, ws.more, ws.knn_index, ws.knn_distance2);
        neighbours = ws.more;
        continue;
      }
      const Neighbour& next = neighbours[used];
      // Security radius: a seed farther than 2 R from s_i is farther from every point of the
      // polygon (within R of s_i) than s_i is, and so are all later ones.
      if (4.0 * radius2 < next.distance2)
        return true;
      ++used;
      switch (clip(finder_, i, next.seed, ws)) {
      case ClipResult::unchanged:
        break;
      case ClipResult::cut:
        radius2 = max_distance2(ws.polygon, seed);
        break;
      case ClipResult::empty:
        emptied_by = next.seed;
        return false;
      }
    }
  }

  VoronoiPiece make_piece(std::int32_t t, std::int32_t i, double area,
                          const std::vector<PolygonVertex>& polygon) const {
    VoronoiPiece piece;
    piece.triangle = t;
    piece.seed = i;
    piece.area = area;
    const std::size_t n = polygon.size();
    for (std::size_t k = 0; k < n; ++k) {
      if (polygon[k].label < 0)
        continue;
      const double length = (polygon[k + 1 == n ? 0 : k + 1].point - polygon[k].point).norm();
      if (length > 0.0)
        piece.borders.emplace_back(polygon[k].label, length);
    }
    std::sort(piece.borders.begin(), piece.borders.end());
    // A round-off re-entry can split one border in two: merge.
    std::size_t kept = 0;
    for (std::size_t b = 0; b < piece.borders.size(); ++b) {
      if (kept > 0 && piece.borders[kept - 1].first == piece.borders[b].first)
        piece.borders[kept - 1].second += piece.borders[b].second;
      else
        piece.borders[kept++] = piece.borders[b];
    }
    piece.borders.resize(kept);
    if (keep_polygons_) {
      piece.polygon.reserve(n);
      piece.edge_labels.reserve(n);
      for (const PolygonVertex& v : polygon) {
        piece.polygon.push_back(v.point);
        piece.edge_labels.push_back(v.label);
      }
    }
    return piece;
  }

  const TriangleMesh& mesh_;
  NeighbourFinder finder_;
  NeighbourCache cache_;
  bool keep_polygons_;
};

} // namespace

std::vector<VoronoiPiece> restricted_voronoi_pieces(const TriangleMesh& mesh,
                                                    std::span<const std::int32_t> triangles,
                                                    std::span<const Vec3> seeds,
                                                    std::span<const std::int64_t> seed_ids,
                                                    bool keep_polygons) {
  TEXSIM_VERIFY(seed_ids.size() == seeds.size(),
                "restricted Voronoi: " << seed_ids.size() << " seed ids for " << seeds.size()
                                       << " seeds");
  TEXSIM_VERIFY(seeds.size() < std::size_t{std::numeric_limits<std::int32_t>::max()},
                "restricted Voronoi: too many seeds (" << seeds.size() << ")");
  std::vector<std::int32_t> order(triangles.begin(), triangles.end());
  std::sort(order.begin(), order.end());
  for (std::size_t r = 0; r < order.size(); ++r) {
    TEXSIM_VERIFY(order[r] >= 0 && order[r] < mesh.num_triangles(),
                  "restricted Voronoi: triangle " << order[r] << " out of range [0, "
                                                  << mesh.num_triangles() << ")");
    TEXSIM_VERIFY(r == 0 || order[r] != order[r - 1],
                  "restricted Voronoi: triangle " << order[r] << " listed twice");
  }
  if (order.empty())
    return {};
  TEXSIM_VERIFY(!seeds.empty(),
                "restricted Voronoi: no seeds for " << order.size() << " triangles");
  for (std::size_t i = 0; i < seeds.size(); ++i)
    TEXSIM_VERIFY(seeds[i].allFinite(), "restricted Voronoi: seed " << i << " is not finite");
  {
    std::vector<std::int64_t> ids(seed_ids.begin(), seed_ids.end());
    std::sort(ids.begin(), ids.end());
    const auto repeated = std::adjacent_find(ids.begin(), ids.end());
    TEXSIM_VERIFY(repeated == ids.end(),
                  "restricted Voronoi: seed id " << *repeated << " given twice");
  }

  RvdBuilder builder(mesh, seeds, seed_ids, keep_polygons);
  const auto count = static_cast<std::int64_t>(order.size());
  std::vector<std::vector<VoronoiPiece>> per_triangle(order.size());
  // The first failure in triangle order is reported, whatever the threads' timing.
  std::int64_t failed_at = count;
  std::exception_ptr failure;
#pragma omp parallel
  {
    Workspace ws(seeds.size());
#pragma omp for schedule(dynamic, 64)
    for (std::int64_t r = 0; r < count; ++r) {
      try {
        per_triangle[r] = builder.triangle_pieces(order[r], ws);
      } catch (...) {
#pragma omp critical(texsim_restricted_voronoi_failure)
        {
          if (r < failed_at) {
            failed_at = r;
            failure = std::current_exception();
          }
        }
      }
    }
  }
  if (failure)
    std::rethrow_exception(failure);

  std::size_t total = 0;
  for (const auto& pieces : per_triangle)
    total += pieces.size();
  std::vector<VoronoiPiece> result;
  result.reserve(total);
  for (auto& pieces : per_triangle)
    std::move(pieces.begin(), pieces.end(), std::back_inserter(result));
  return result;
}

} // namespace texsim::geom
