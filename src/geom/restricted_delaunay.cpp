#include "geom/restricted_delaunay.hpp"

#include "core/error.hpp"
#include "geom/distributed_triangles.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/morton_order.hpp"
#include "geom/point_halo.hpp"
#include "geom/point_kd_tree.hpp"
#include "geom/restricted_voronoi.hpp"
#include "par/allgather_runs.hpp"
#include "par/collective.hpp"
#include "par/gather_to_root.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"

#include <Eigen/Geometry>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <utility>

namespace texsim::geom {
namespace {

/// Relative tolerance of "equally far" for the seeds meeting at a Voronoi vertex (see the header).
constexpr double kMeetingTolerance = 1e-9;

// Written out so that the value is the same in every build (as in restricted_voronoi.cpp).
double squared_distance(const Vec3& a, const Vec3& b) {
  const double dx = a.x() - b.x();
  const double dy = a.y() - b.y();
  const double dz = a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

/// What the dual needs of one piece once its polygon is gone: restricted_delaunay computes the
/// pieces a chunk of triangles at a time and keeps only this, so the polygons of the whole surface
/// are never held at once.
struct PieceSummary {
  std::int32_t triangle = -1;
  std::int32_t seed = -1;
  double area = 0.0;
  /// Into DualInput::borders. In the parallel join rank 0 holds the borders of the handed-over
  /// pieces only (PieceOwners::orphan_pieces, fetched from the cutting ranks); the others have
  /// none.
  std::uint32_t first_border = 0;
  std::uint32_t border_count = 0;
  /// Bit c: a boundary edge of the piece runs along side c (corners c, c + 1) of its triangle, so
  /// the piece may join its seed's piece across that side.
  std::uint8_t linked_sides = 0;
};

/// A corner of a piece between two bisector edges, where the cells of the piece's seed and of
/// `a` and `b` meet.
struct Meeting {
  std::int32_t piece;
  std::int32_t a;
  std::int32_t b;
  /// Into DualInput::meeting_points, or -1: no other seed is as far from the corner as these three
  /// (CrowdedMeetingTest), so the corner itself is not needed.
  std::int32_t point;
};

/// The pieces of every triangle, reduced to what the dual needs, in (triangle, seed id) order.
struct DualInput {
  std::vector<PieceSummary> pieces;
  std::vector<std::pair<std::int32_t, double>> borders; ///< VoronoiPiece::borders, concatenated
  std::vector<Meeting> meetings;
  std::vector<Vec3> meeting_points; ///< of the meetings CrowdedMeetingTest flagged
  /// (seed, seed) pairs whose cells share a border somewhere, both ways, sorted and unique.
  std::vector<std::pair<std::int32_t, std::int32_t>> neighbour_pairs;
  /// The largest distance from a piece's seed to its polygon's vertices (not sent).
  double largest_piece_radius = 0.0;
};

/// The sides of its triangle along which `piece`'s boundary edges (label -1) run: for each such
/// edge, the side nearest to both its ends.
std::uint8_t linked_sides(const TriangleMesh& surface, const VoronoiPiece& piece) {
  const Triangle& tri = surface.triangles[std::size_t(piece.triangle)];
  const std::size_t n = piece.polygon.size();
  std::uint8_t sides = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& from = piece.polygon[k];
    const Vec3& to = piece.polygon[(k + 1) % n];
    if (piece.edge_labels[k] >= 0 || from == to)
      continue;
    int side = 0;
    double nearest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 3; ++c) {
      const Vec3& a = surface.positions[std::size_t(tri[std::size_t(c)])];
      const Vec3 along =
          (surface.positions[std::size_t(tri[std::size_t((c + 1) % 3)])] - a).normalized();
      const double off = std::max((from - a).cross(along).norm(), (to - a).cross(along).norm());
      if (off < nearest) {
        nearest = off;
        side = c;
      }
    }
    sides = std::uint8_t(sides | (1u << side));
  }
  return sides;
}

/// Sorts `pairs`, whose runs ending at `run_ends` are each sorted already, and drops repeated
/// pairs: the runs are merged two by two, log2(runs) passes instead of a full sort.
void merge_sorted_runs(std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
                       std::vector<std::size_t> run_ends) {
  std::vector<std::size_t> bounds = {0};
  bounds.insert(bounds.end(), run_ends.begin(), run_ends.end());
  while (bounds.size() > 2) {
    std::vector<std::size_t> merged = {0};
    for (std::size_t k = 0; k + 2 < bounds.size(); k += 2) {
      const auto at = [&](std::size_t b) { return pairs.begin() + std::ptrdiff_t(bounds[b]); };
      std::inplace_merge(at(k), at(k + 1), at(k + 2));
      merged.push_back(bounds[k + 2]);
    }
    if (bounds.size() % 2 == 0) // an odd number of runs: the last one waits for the next pass
      merged.push_back(bounds.back());
    bounds = std::move(merged);
  }
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

/// The squared distance from a meeting point to the piece's seed, and the test of whether
/// another seed is as far within the tolerance, so that its cell meets there too.
struct MeetingDistance {
  MeetingDistance(const Vec3& point, const Vec3& seed)
      : point(point), reference(squared_distance(point, seed)),
        tolerance(kMeetingTolerance * (point.cwiseAbs().maxCoeff() + std::sqrt(reference)) *
                  std::sqrt(reference)) {}
  bool as_far(const Vec3& other) const {
    return std::abs(squared_distance(point, other) - reference) <= tolerance;
  }
  const Vec3& point;
  double reference;
  double tolerance;
};

/// Whether any seed but i, a and b, among those a rank cut against, is as far from a meeting
/// point p as i within the tolerance. When none is, MeetingTriangulator, which asks only the
/// neighbours of i, a and b, finds none either: a neighbour c of a cell x among them shares a
/// border point y with it, so |c - p| <= |c - y| + |y - x| + |x - p| <= 3 R (R the largest piece
/// radius: y and p lie on pieces of x, a and b being as far from p as i), and the seeds within
/// the halo (>= 3 R, checked) of a rank's triangles are among those it cut against. So only the
/// flagged meetings (a handful) keep their point.
class CrowdedMeetingTest {
public:
  explicit CrowdedMeetingTest(std::span<const Vec3> seeds)
      : seeds_(seeds), cloud_{seeds},
        tree_(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(12)) {}

  bool operator()(const Vec3& point, std::int32_t i, std::int32_t a, std::int32_t b) const {
    FirstOtherSeed search(*this, point, i, a, b);
    tree_.radiusSearchCustomCallback(point.data(), search,
                                     nanoflann::SearchParams(32, 0.0f, false));
    return search.found;
  }

private:
  /// nanoflann's result set: stops at the first seed but i, a and b within the tolerance.
  struct FirstOtherSeed {
    FirstOtherSeed(const CrowdedMeetingTest& test, const Vec3& point, std::int32_t i,
                   std::int32_t a, std::int32_t b)
        : test(test), distance(point, test.seeds_[std::size_t(i)]), i(i), a(a), b(b),
          // nanoflann's squared distances may differ from ours by a few ulps: a wider ball.
          radius((distance.reference + distance.tolerance) * (1.0 + 1e-9) + 1e-300) {}
    void init() {}
    void clear() {}
    std::size_t size() const { return found ? 1 : 0; }
    bool full() const { return true; }
    double worstDist() const { return radius; }
    bool addPoint(double, std::uint32_t index) {
      const auto c = std::int32_t(index);
      if (c != i && c != a && c != b && distance.as_far(test.seeds_[index]))
        found = true;
      return !found;
    }

    const CrowdedMeetingTest& test;
    MeetingDistance distance;
    std::int32_t i, a, b;
    double radius;
    bool found = false;
  };

  std::span<const Vec3> seeds_;
  PointCloudView cloud_;
  PointKdTree tree_;
};

/// Appends the summaries, borders, meetings and neighbour pairs of `pieces` (of triangles after
/// every triangle already in `input`), cut against `seeds`. With `global` (one entry per seed),
/// the seeds are a part of a larger set and the input speaks that set's indices: seed index i
/// becomes global[i], each piece's borders sorted again by them.
void add_pieces(const TriangleMesh& surface, std::span<const VoronoiPiece> pieces,
                const CrowdedMeetingTest& crowded, std::span<const std::int32_t> global,
                DualInput& input) {
  const auto global_of = [&](std::int32_t seed) {
    return global.empty() ? seed : global[std::size_t(seed)];
  };
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  for (const VoronoiPiece& piece : pieces) {
    const auto index = std::int32_t(input.pieces.size());
    const std::int32_t seed = global_of(piece.seed);
    input.pieces.push_back({piece.triangle, seed, piece.area, std::uint32_t(input.borders.size()),
                            std::uint32_t(piece.borders.size()), linked_sides(surface, piece)});
    const auto first_border = std::ptrdiff_t(input.borders.size());
    for (const auto& [other, length] : piece.borders)
      input.borders.emplace_back(global_of(other), length);
    if (!global.empty())
      std::sort(input.borders.begin() + first_border, input.borders.end());
    const auto& labels = piece.edge_labels;
    const std::size_t n = labels.size();
    for (std::size_t k = 0; k < n; ++k) {
      const std::int32_t before = labels[(k + n - 1) % n], after = labels[k];
      // Equal labels: a border split in two by a round-off re-entry, not a meeting.
      if (before >= 0 && after >= 0 && before != after) {
        std::int32_t point = -1;
        if (crowded(piece.polygon[k], piece.seed, before, after)) {
          point = std::int32_t(input.meeting_points.size());
          input.meeting_points.push_back(piece.polygon[k]);
        }
        input.meetings.push_back({index, global_of(before), global_of(after), point});
      }
      if (after >= 0) {
        pairs.emplace_back(seed, global_of(after));
        pairs.emplace_back(global_of(after), seed);
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  const std::size_t fresh = pairs.size();
  pairs.insert(pairs.end(), input.neighbour_pairs.begin(), input.neighbour_pairs.end());
  merge_sorted_runs(pairs, {fresh, pairs.size()});
  input.neighbour_pairs = std::move(pairs);
}

/// Seeds whose cells share a border (of any length) somewhere on the surface, per seed.
CsrAdjacency voronoi_neighbours(const DualInput& input, std::size_t num_seeds) {
  CsrAdjacency adjacency;
  adjacency.offsets.assign(num_seeds + 1, 0);
  adjacency.indices.reserve(input.neighbour_pairs.size());
  for (const auto& [from, to] : input.neighbour_pairs) {
    ++adjacency.offsets[std::size_t(from) + 1];
    adjacency.indices.push_back(to);
  }
  std::partial_sum(adjacency.offsets.begin(), adjacency.offsets.end(), adjacency.offsets.begin());
  return adjacency;
}

/// Which cell each piece's region counts for in the dual. A seed's 3D Voronoi cell can meet the
/// surface in several connected components (the surface folds back into it: thin parts, creases,
/// saddles); its largest component keeps the seed, every other one is handed to the neighbour
/// sharing the longest border with it, so that the dual is that of a tiling by connected cells.
class PieceOwners {
public:
  /// Groups the pieces into connected components and finds each seed's largest; the pieces of
  /// the others are orphan_pieces(), which hand_over_orphans() assigns once `input` holds their
  /// borders.
  PieceOwners(const TriangleMesh& surface, std::size_t num_seeds, const DualInput& input)
      : input_(input), first_piece_(std::size_t(surface.num_triangles()) + 1, 0),
        owner_(input.pieces.size()) {
    for (const PieceSummary& piece : input.pieces)
      ++first_piece_[std::size_t(piece.triangle) + 1];
    std::partial_sum(first_piece_.begin(), first_piece_.end(), first_piece_.begin());
    for (std::size_t p = 0; p < input.pieces.size(); ++p)
      owner_[p] = input.pieces[p].seed;
    find_orphans(num_seeds, components(surface));
  }

  /// The pieces outside their seed's largest component, in increasing order.
  const std::vector<std::size_t>& orphan_pieces() const { return orphans_; }

  /// Hands each orphan component to the neighbour sharing the longest border with it (the
  /// borders of orphan_pieces() are read from the input).
  void hand_over_orphans(std::span<const std::int64_t> seed_ids) {
    // Border lengths of every orphan component with its neighbours, summed in piece order.
    std::map<std::size_t, std::map<std::int32_t, double>> orphan_borders;
    for (std::size_t k = 0; k < orphans_.size(); ++k) {
      const PieceSummary& piece = input_.pieces[orphans_[k]];
      auto& borders = orphan_borders[orphan_roots_[k]];
      const auto first = input_.borders.begin() + piece.first_border;
      for (auto border = first; border != first + piece.border_count; ++border)
        borders[border->first] += border->second;
    }
    std::map<std::size_t, std::int32_t> heir;
    for (const auto& [component, borders] : orphan_borders) {
      std::int32_t best = -1;
      for (const auto& [other, length] : borders)
        if (best < 0 || length > borders.at(best) ||
            (length == borders.at(best) &&
             seed_ids[std::size_t(other)] < seed_ids[std::size_t(best)]))
          best = other;
      if (best >= 0)
        heir[component] = best;
    }
    for (std::size_t k = 0; k < orphans_.size(); ++k)
      if (const auto found = heir.find(orphan_roots_[k]); found != heir.end())
        owner_[orphans_[k]] = found->second;
  }

  /// The cell whose region `cell`'s piece in triangle t counts for: `cell` itself unless that piece
  /// is a handed-over component (or `cell` has no piece in t), followed through further hand-overs.
  std::int32_t owner(std::int32_t cell, std::int32_t t) const {
    for (int hop = 0; hop < kMaxHops; ++hop) {
      const std::int64_t p = piece_of(cell, t);
      if (p < 0 || owner_[std::size_t(p)] == cell)
        return cell;
      cell = owner_[std::size_t(p)];
    }
    return cell;
  }

private:
  /// Hand-overs followed from one piece (a chain longer than this would need nested orphans).
  static constexpr int kMaxHops = 4;

  std::int64_t piece_of(std::int32_t cell, std::int32_t t) const {
    for (std::size_t p = first_piece_[std::size_t(t)]; p < first_piece_[std::size_t(t) + 1]; ++p)
      if (input_.pieces[p].seed == cell)
        return std::int64_t(p);
    return -1;
  }

  /// Union-find root of every piece: pieces of one seed in two triangles are connected when both
  /// touch their shared edge along a segment (the cell, convex, meets the edge in one segment).
  std::vector<std::size_t> components(const TriangleMesh& surface) const {
    const MeshTopology topology(surface);
    const auto& pieces = input_.pieces;
    std::vector<std::size_t> parent(pieces.size());
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    const auto root = [&](std::size_t p) {
      while (parent[p] != p)
        p = parent[p] = parent[parent[p]];
      return p;
    };
    for (std::size_t p = 0; p < pieces.size(); ++p) {
      const PieceSummary& piece = pieces[p];
      for (int side = 0; side < 3; ++side) {
        if (!(piece.linked_sides & (1u << side)))
          continue;
        const std::int32_t edge =
            topology.triangle_edges(piece.triangle)[std::size_t(side + 2) % 3];
        const auto across = topology.edge_triangles(edge);
        if (across.size() != 2)
          continue;
        const std::int32_t other = across[0] == piece.triangle ? across[1] : across[0];
        const std::int64_t q = piece_of(piece.seed, other);
        if (q >= 0)
          parent[root(p)] = root(std::size_t(q));
      }
    }
    for (std::size_t p = 0; p < pieces.size(); ++p)
      parent[p] = root(p);
    return parent;
  }

  void find_orphans(std::size_t num_seeds, const std::vector<std::size_t>& root) {
    const auto& pieces = input_.pieces;
    std::vector<double> component_area(pieces.size(), 0.0);
    for (std::size_t p = 0; p < pieces.size(); ++p)
      component_area[root[p]] += pieces[p].area;
    // Each seed's largest component (exact ties: the first in piece order).
    std::vector<std::int64_t> main_root(num_seeds, -1);
    for (std::size_t p = 0; p < pieces.size(); ++p) {
      std::int64_t& best = main_root[std::size_t(pieces[p].seed)];
      if (best < 0 || component_area[root[p]] > component_area[std::size_t(best)])
        best = std::int64_t(root[p]);
    }
    for (std::size_t p = 0; p < pieces.size(); ++p)
      if (std::int64_t(root[p]) != main_root[std::size_t(pieces[p].seed)]) {
        orphans_.push_back(p);
        orphan_roots_.push_back(root[p]);
      }
  }

  const DualInput& input_;
  std::vector<std::size_t> first_piece_;  ///< per triangle: its first piece (pieces sorted by it)
  std::vector<std::int32_t> owner_;       ///< per piece
  std::vector<std::size_t> orphans_;      ///< the pieces outside their seed's largest component
  std::vector<std::size_t> orphan_roots_; ///< each orphan's component (its union-find root)
};

class MeetingTriangulator {
public:
  MeetingTriangulator(const TriangleMesh& surface, std::span<const Vec3> seeds,
                      std::span<const std::int64_t> seed_ids, const DualInput& input,
                      const PieceOwners& owners)
      : surface_(surface), seeds_(seeds), ids_(seed_ids), input_(input),
        neighbours_(voronoi_neighbours(input, seeds.size())), owners_(owners) {}

  /// Appends the triangles of one meeting to `out`, counter-clockwise: (seed, a, b) when exactly
  /// three cells meet there, else the fan of every meeting seed from the smallest id; then each
  /// cell replaced by the one its piece there counts for (PieceOwners), triangles left with a
  /// repeated cell dropped. Allocates nothing when three cells meet (nearly every meeting).
  void add_triangles(const Meeting& meeting, std::vector<Triangle>& out) const {
    const PieceSummary& piece = input_.pieces[std::size_t(meeting.piece)];
    const auto add = [&](Triangle triangle) {
      for (std::int32_t& cell : triangle)
        cell = owners_.owner(cell, piece.triangle);
      if (triangle[0] != triangle[1] && triangle[1] != triangle[2] && triangle[2] != triangle[0])
        out.push_back(triangle);
    };
    // Every seed as far from the point as the piece's within the tolerance: none but a and b
    // unless the cut flagged the meeting (found without allocating), else the fan of them all.
    const std::int32_t i = piece.seed;
    std::vector<std::int32_t> meeting_seeds;
    const Vec3* point =
        meeting.point < 0 ? nullptr : &input_.meeting_points[std::size_t(meeting.point)];
    if (point)
      add_other_meeting_seeds(*point, i, meeting.a, meeting.b, meeting_seeds);
    if (meeting_seeds.empty()) {
      add({i, meeting.a, meeting.b});
      return;
    }
    meeting_seeds.insert(meeting_seeds.end(), {i, meeting.a, meeting.b});
    std::sort(meeting_seeds.begin(), meeting_seeds.end());
    meeting_seeds.erase(std::unique(meeting_seeds.begin(), meeting_seeds.end()),
                        meeting_seeds.end());
    order_around(*point, piece.triangle, meeting_seeds);
    for (std::size_t s = 1; s + 1 < meeting_seeds.size(); ++s)
      add({meeting_seeds[0], meeting_seeds[s], meeting_seeds[s + 1]});
  }

private:
  /// Appends to `found` every neighbour of i, a and b other than these three as far from `point`
  /// as i within the tolerance (some perhaps twice); a seed that borders none of the three cells
  /// cannot meet them there.
  void add_other_meeting_seeds(const Vec3& point, std::int32_t i, std::int32_t a, std::int32_t b,
                               std::vector<std::int32_t>& found) const {
    const MeetingDistance distance(point, seeds_[std::size_t(i)]);
    for (const std::int32_t cell : {i, a, b})
      for (const std::int32_t c : neighbours_.row(cell))
        if (c != i && c != a && c != b && distance.as_far(seeds_[std::size_t(c)]))
          found.push_back(c);
  }

  /// Sorts `cells` counter-clockwise around `point` about the normal of surface triangle t, the
  /// smallest id first.
  void order_around(const Vec3& point, std::int32_t t, std::vector<std::int32_t>& cells) const {
    const Triangle& tri = surface_.triangles[std::size_t(t)];
    const Vec3& corner = surface_.positions[std::size_t(tri[0])];
    const Vec3 u = (surface_.positions[std::size_t(tri[1])] - corner).normalized();
    const Vec3 normal = u.cross(surface_.positions[std::size_t(tri[2])] - corner).normalized();
    const Vec3 v = normal.cross(u);
    std::vector<std::pair<double, std::int32_t>> angles;
    for (const std::int32_t c : cells) {
      const Vec3 w = seeds_[std::size_t(c)] - point;
      angles.emplace_back(std::atan2(w.dot(v), w.dot(u)), c);
    }
    std::sort(angles.begin(), angles.end(), [this](const auto& x, const auto& y) {
      return x.first < y.first ||
             (x.first == y.first && ids_[std::size_t(x.second)] < ids_[std::size_t(y.second)]);
    });
    for (std::size_t s = 0; s < cells.size(); ++s)
      cells[s] = angles[s].second;
    const auto first = std::min_element(cells.begin(), cells.end(), [this](auto x, auto y) {
      return ids_[std::size_t(x)] < ids_[std::size_t(y)];
    });
    std::rotate(cells.begin(), first, cells.end());
  }

  const TriangleMesh& surface_;
  std::span<const Vec3> seeds_;
  std::span<const std::int64_t> ids_;
  const DualInput& input_;
  CsrAdjacency neighbours_;
  const PieceOwners& owners_;
};

/// One sighting of a triangle: its vertices in increasing id order and whether it was seen in that
/// cyclic order (+1) or the other (-1).
struct Sighting {
  Triangle vertices;
  int vote;
};

Sighting sighting_of(const Triangle& t, std::span<const std::int64_t> seed_ids) {
  Triangle sorted = t;
  std::sort(sorted.begin(), sorted.end(),
            [&](auto x, auto y) { return seed_ids[std::size_t(x)] < seed_ids[std::size_t(y)]; });
  // The sorted order is the same cycle as t when t is one of its rotations.
  const bool same_cycle = (t[0] == sorted[0] && t[1] == sorted[1]) ||
                          (t[1] == sorted[0] && t[2] == sorted[1]) ||
                          (t[2] == sorted[0] && t[0] == sorted[1]);
  return {sorted, same_cycle ? 1 : -1};
}

/// One triangle for each set of sightings of the same vertices, oriented as most of them say
/// (ties: the vertices in increasing id order), sorted by the vertices' ids. The sightings are
/// put in buckets by their first vertex (the smallest id), and the buckets visited in id order,
/// each sorted by its other two ids: a full sort of the sightings by their ids took longer than
/// finding them.
std::vector<Triangle> voted_triangles(std::span<const Sighting> sightings,
                                      std::span<const std::int64_t> seed_ids) {
  TEXSIM_VERIFY(sightings.size() < std::size_t(std::numeric_limits<std::uint32_t>::max()),
                "restricted_delaunay: more than 2^32 sightings of triangles");
  std::vector<std::uint32_t> bucket_begin(seed_ids.size() + 1, 0);
  for (const Sighting& sighting : sightings)
    ++bucket_begin[std::size_t(sighting.vertices[0]) + 1];
  std::partial_sum(bucket_begin.begin(), bucket_begin.end(), bucket_begin.begin());
  std::vector<std::uint32_t> bucketed(sightings.size());
  {
    std::vector<std::uint32_t> next(bucket_begin.begin(), bucket_begin.end() - 1);
    for (std::size_t s = 0; s < sightings.size(); ++s)
      bucketed[next[std::size_t(sightings[s].vertices[0])]++] = std::uint32_t(s);
  }
  std::vector<std::int32_t> in_id_order(seed_ids.size());
  std::iota(in_id_order.begin(), in_id_order.end(), 0);
  std::sort(in_id_order.begin(), in_id_order.end(),
            [&](auto x, auto y) { return seed_ids[std::size_t(x)] < seed_ids[std::size_t(y)]; });
  // The other two ids of a sighting (equal ids: equal vertices, the ids being all different).
  const auto rest = [&](std::uint32_t s) {
    const Triangle& v = sightings[s].vertices;
    return std::pair(seed_ids[std::size_t(v[1])], seed_ids[std::size_t(v[2])]);
  };
  std::vector<Triangle> triangles;
  for (const std::int32_t first : in_id_order) {
    const auto begin = bucketed.begin() + bucket_begin[std::size_t(first)];
    const auto end = bucketed.begin() + bucket_begin[std::size_t(first) + 1];
    std::sort(begin, end, [&](auto x, auto y) { return rest(x) < rest(y); });
    for (auto group = begin; group != end;) {
      int votes = 0;
      auto after = group;
      for (; after != end && rest(*after) == rest(*group); ++after)
        votes += sightings[*after].vote;
      const Triangle& v = sightings[*group].vertices;
      triangles.push_back(votes >= 0 ? v : Triangle{v[0], v[2], v[1]});
      group = after;
    }
  }
  return triangles;
}

/// The dual input of every triangle of `surface`, computed `chunk_triangles` at a time. With
/// `global` (one entry per seed), the seeds are a part of a larger set and the dual input speaks
/// that set's indices: seed index i becomes global[i].
DualInput dual_input(const TriangleMesh& surface, std::span<const Vec3> seeds,
                     std::span<const std::int64_t> seed_ids, std::int32_t chunk_triangles,
                     std::span<const std::int32_t> global = {}) {
  TEXSIM_VERIFY(chunk_triangles > 0,
                "restricted_delaunay: chunk_triangles " << chunk_triangles << " is not positive");
  DualInput input;
  const CrowdedMeetingTest crowded(seeds);
  std::vector<std::int32_t> chunk;
  for (std::int32_t first = 0; first < surface.num_triangles(); first += chunk_triangles) {
    chunk.resize(std::size_t(std::min(chunk_triangles, surface.num_triangles() - first)));
    std::iota(chunk.begin(), chunk.end(), first);
    const auto pieces = restricted_voronoi_pieces(surface, chunk, seeds, seed_ids, true);
    for (const VoronoiPiece& piece : pieces)
      for (const Vec3& corner : piece.polygon)
        input.largest_piece_radius =
            std::max(input.largest_piece_radius, (corner - seeds[std::size_t(piece.seed)]).norm());
    add_pieces(surface, pieces, crowded, global, input);
  }
  return input;
}

/// The triangles of the dual of the pieces in `input` (of `surface`'s triangles), each piece
/// counting for the cell `owners` (orphans handed over) says.
TriangleMesh dual_mesh(const TriangleMesh& surface, std::span<const Vec3> seeds,
                       std::span<const std::int64_t> seed_ids, const DualInput& input,
                       const PieceOwners& owners) {
  TEXSIM_VERIFY(input.pieces.size() < std::size_t(std::numeric_limits<std::int32_t>::max()) &&
                    input.borders.size() < std::size_t(std::numeric_limits<std::uint32_t>::max()),
                "restricted_delaunay: more than 2^31 Voronoi pieces");

  const MeetingTriangulator triangulator(surface, seeds, seed_ids, input, owners);
  const auto& meetings = input.meetings;
  // Each thread keeps its meetings' sightings in one vector (not a vector per meeting, which cost
  // more than the sightings themselves). The order in which they are joined does not matter:
  // voted_triangles groups equal triangles, whose vertices are the same and whose votes are
  // summed.
  std::vector<std::vector<Sighting>> per_thread(static_cast<std::size_t>(omp_get_max_threads()));
  const auto count = static_cast<std::int64_t>(meetings.size());
#pragma omp parallel
  {
    std::vector<Sighting>& mine = per_thread[std::size_t(omp_get_thread_num())];
    // Nearly every meeting gives one triangle (a fan of a crowded meeting more, a triangle with
    // a repeated cell none): room for this thread's share and a little more, so the vector does
    // not double past the sightings (at the doubling, both copies are held); the first thread's
    // takes the others' afterwards.
    const auto share = omp_get_thread_num() == 0 ? count : count / omp_get_num_threads() + 1;
    mine.reserve(std::size_t(share + share / 32 + 16));
    std::vector<Triangle> found;
#pragma omp for schedule(static)
    for (std::int64_t m = 0; m < count; ++m) {
      found.clear();
      triangulator.add_triangles(meetings[std::size_t(m)], found);
      for (const Triangle& t : found)
        mine.push_back(sighting_of(t, seed_ids));
    }
  }
  // The first thread's part takes the others (with one thread, nothing is copied).
  std::vector<Sighting> sightings = std::move(per_thread.front());
  for (std::size_t t = 1; t < per_thread.size(); ++t) {
    sightings.insert(sightings.end(), per_thread[t].begin(), per_thread[t].end());
    per_thread[t] = std::vector<Sighting>();
  }
  TriangleMesh mesh;
  mesh.positions.assign(seeds.begin(), seeds.end());
  mesh.triangles = voted_triangles(sightings, seed_ids);
  return mesh;
}

/// The counts at the head of a serialized dual input: pieces, meetings, meeting points, neighbour
/// pairs.
using DualInputCounts = std::array<std::uint64_t, 4>;

/// A rank's dual input on the wire: counts, then the pieces, the meetings, their points and the
/// neighbour pairs, as plain numbers. The borders stay with the rank: rank 0 asks for those of
/// the handed-over pieces only (fetch_orphan_borders).
std::vector<std::byte> serialize(const DualInput& input) {
  std::vector<std::byte> bytes;
  constexpr std::size_t kPieceBytes =
      2 * sizeof(std::int32_t) + sizeof(double) + sizeof(std::uint8_t);
  constexpr std::size_t kMeetingBytes = 4 * sizeof(std::int32_t);
  bytes.reserve(sizeof(DualInputCounts) + input.pieces.size() * kPieceBytes +
                input.meetings.size() * kMeetingBytes + input.meeting_points.size() * sizeof(Vec3) +
                input.neighbour_pairs.size() * 2 * sizeof(std::int32_t));
  const auto put = [&bytes](const auto& value) {
    const auto* raw = reinterpret_cast<const std::byte*>(&value);
    bytes.insert(bytes.end(), raw, raw + sizeof(value));
  };
  put(std::uint64_t(input.pieces.size()));
  put(std::uint64_t(input.meetings.size()));
  put(std::uint64_t(input.meeting_points.size()));
  put(std::uint64_t(input.neighbour_pairs.size()));
  for (const PieceSummary& piece : input.pieces) {
    put(piece.triangle);
    put(piece.seed);
    put(piece.area);
    put(piece.linked_sides);
  }
  for (const Meeting& meeting : input.meetings) {
    put(meeting.piece);
    put(meeting.a);
    put(meeting.b);
    put(meeting.point);
  }
  for (const Vec3& point : input.meeting_points) {
    put(point.x());
    put(point.y());
    put(point.z());
  }
  for (const auto& [from, to] : input.neighbour_pairs) {
    put(from);
    put(to);
  }
  return bytes;
}

/// Reserves on rank 0 room in `input` for every rank's serialized part (`mine` on each rank), so
/// that appending them does not grow the vectors by doubling: up to twice their size, and both
/// copies while one grows. Collective.
void reserve_for_parts(const par::Comm& comm, std::span<const std::byte> mine, DualInput& input) {
  DualInputCounts counts{};
  std::memcpy(counts.data(), mine.data(), sizeof(counts));
  const auto all = par::gather_to_root(comm, std::span<const DualInputCounts>(&counts, 1));
  DualInputCounts total{};
  for (const DualInputCounts& part : all)
    for (std::size_t k = 0; k < total.size(); ++k)
      total[k] += part[k];
  input.pieces.reserve(total[0]);
  input.meetings.reserve(total[1]);
  input.meeting_points.reserve(total[2]);
  input.neighbour_pairs.reserve(total[3]);
}

/// Appends a rank's serialized dual input, whose triangles start at `first_triangle`, to `input`:
/// its triangle, piece and meeting-point indices are moved past the ones already there (its pieces
/// come without borders). Appending the ranks' parts in order gives the serial input once the
/// neighbour pairs, sorted within each part, are merged (once at the end: merging at every rank
/// would cost ranks x pairs).
void append(std::span<const std::byte> bytes, std::int32_t first_triangle, DualInput& input) {
  std::size_t at = 0;
  const auto get = [&bytes, &at](auto& value) {
    std::memcpy(&value, bytes.data() + at, sizeof(value));
    at += sizeof(value);
  };
  std::uint64_t pieces = 0, meetings = 0, points = 0, pairs = 0;
  get(pieces);
  get(meetings);
  get(points);
  get(pairs);
  const auto first_piece = std::int32_t(input.pieces.size());
  for (std::uint64_t p = 0; p < pieces; ++p) {
    PieceSummary piece;
    get(piece.triangle);
    get(piece.seed);
    get(piece.area);
    get(piece.linked_sides);
    piece.triangle += first_triangle;
    input.pieces.push_back(piece);
  }
  const auto first_point = std::int32_t(input.meeting_points.size());
  for (std::uint64_t m = 0; m < meetings; ++m) {
    Meeting meeting{};
    get(meeting.piece);
    get(meeting.a);
    get(meeting.b);
    get(meeting.point);
    meeting.piece += first_piece;
    if (meeting.point >= 0)
      meeting.point += first_point;
    input.meetings.push_back(meeting);
  }
  for (std::uint64_t p = 0; p < points; ++p) {
    double x = 0, y = 0, z = 0;
    get(x);
    get(y);
    get(z);
    input.meeting_points.emplace_back(x, y, z);
  }
  for (std::uint64_t k = 0; k < pairs; ++k) {
    std::pair<std::int32_t, std::int32_t> pair;
    get(pair.first);
    get(pair.second);
    input.neighbour_pairs.push_back(pair);
  }
  TEXSIM_VERIFY(at == bytes.size(), "restricted_delaunay: a rank's dual input has trailing bytes");
}

/// A rank's pieces' borders, kept after its dual input went to rank 0: piece k's are
/// borders[begin[k]] .. borders[begin[k + 1] - 1].
struct KeptBorders {
  std::vector<std::uint32_t> begin;
  std::vector<std::pair<std::int32_t, double>> borders;
};

KeptBorders keep_borders(DualInput& input) {
  KeptBorders kept;
  kept.begin.reserve(input.pieces.size() + 1);
  for (const PieceSummary& piece : input.pieces)
    kept.begin.push_back(piece.first_border);
  kept.begin.push_back(std::uint32_t(input.borders.size()));
  kept.borders = std::move(input.borders);
  return kept;
}

/// Rank 0's request for a piece's borders: its index among all pieces and among its rank's.
struct BorderRequest {
  std::int32_t piece;
  std::int32_t local;
};

/// One border of a requested piece.
struct BorderRecord {
  std::int32_t piece;
  std::int32_t seed;
  double length;
};

/// Gives rank 0's `input` the borders of pieces `orphans` (increasing indices into input.pieces,
/// rank r's pieces starting at piece_begin[r]) from the ranks that cut them and kept them. A
/// handful of pieces instead of every piece's borders (about 3.5 per piece, 16 bytes each).
/// Collective; `orphans` and `piece_begin` are read on rank 0 only.
void fetch_orphan_borders(const par::Comm& comm, std::span<const std::size_t> orphans,
                          std::span<const std::size_t> piece_begin, const KeptBorders& kept,
                          DualInput& input) {
  std::vector<std::vector<BorderRequest>> requests(std::size_t(comm.size));
  for (const std::size_t p : orphans) {
    const auto rank = std::size_t(std::upper_bound(piece_begin.begin(), piece_begin.end(), p) -
                                  piece_begin.begin()) -
                      1;
    requests[rank].push_back({std::int32_t(p), std::int32_t(p - piece_begin[rank])});
  }
  const auto asked = par::exchange_records(comm, std::move(requests));
  std::vector<std::vector<BorderRecord>> answers(std::size_t(comm.size));
  for (const BorderRequest& request : asked)
    for (auto b = kept.begin[std::size_t(request.local)];
         b < kept.begin[std::size_t(request.local) + 1]; ++b)
      answers[0].push_back({request.piece, kept.borders[b].first, kept.borders[b].second});
  // From rank 0 in increasing piece order, each rank's pieces in order: each piece's borders
  // arrive together.
  for (const BorderRecord& border : par::exchange_records(comm, std::move(answers))) {
    PieceSummary& piece = input.pieces[std::size_t(border.piece)];
    if (piece.border_count == 0)
      piece.first_border = std::uint32_t(input.borders.size());
    ++piece.border_count;
    input.borders.emplace_back(border.seed, border.length);
  }
}

/// Seeds a rank cuts its triangles against, and each one's index among all seeds (rank order).
struct SeedView {
  std::vector<Vec3> positions;
  std::vector<std::int64_t> ids;
  std::vector<std::int32_t> global;
};

/// `surface` with its triangles along a Morton curve of their centroids.
TriangleMesh along_morton_curve(const TriangleMesh& surface) {
  TriangleMesh curve;
  curve.positions = surface.positions;
  curve.triangles.reserve(surface.triangles.size());
  for (const std::size_t t : morton_triangle_order(surface))
    curve.triangles.push_back(surface.triangles[t]);
  return curve;
}

/// This rank's even run of rank 0's triangles, as separate corners: rank 0 sends each rank its run
/// as corner positions.
TriangleMesh triangles_from_root(const par::Comm& comm, const TriangleMesh& root_surface) {
  using Corners = std::array<double, 9>;
  std::vector<std::vector<Corners>> outgoing(std::size_t(comm.size));
  if (comm.is_root()) {
    const std::int64_t triangles = root_surface.num_triangles();
    for (int r = 0; r < comm.size; ++r)
      for (auto t = par::even_run_begin(triangles, r, comm.size);
           t < par::even_run_begin(triangles, r + 1, comm.size); ++t)
        outgoing[std::size_t(r)].push_back(corners_of(root_surface, std::size_t(t)));
  }
  const std::vector<Corners> mine = par::exchange_records(comm, std::move(outgoing));
  TriangleMesh share;
  for (const Corners& corners : mine) {
    const auto first = std::int32_t(share.positions.size());
    for (std::size_t c = 0; c < 3; ++c)
      share.positions.emplace_back(corners[3 * c], corners[3 * c + 1], corners[3 * c + 2]);
    share.triangles.push_back({first, first + 1, first + 2});
  }
  return share;
}

/// Boxes holding every point within `halo` of a share's triangles (corners 3 t, 3 t + 1, 3 t + 2):
/// every point of a triangle lies within its longest edge of a corner, so boxes around the
/// corners grown by halo + that edge hold them (one box per occupied grid cell, as SurfaceCells'
/// halo). Triangles with an edge longer than halo / 4 (slivers, filled holes) get a box of their
/// own, so that a few long edges do not widen every box.
std::vector<Box3> halo_boxes(const TriangleMesh& share, double halo) {
  const double long_edge = halo / 4.0;
  std::vector<Vec3> corners;
  std::vector<Box3> boxes;
  double longest_short = 0.0;
  for (std::size_t t = 0; t < share.triangles.size(); ++t) {
    const std::span<const Vec3> triangle(share.positions.data() + 3 * t, 3);
    double longest = 0.0;
    for (std::size_t c = 0; c < 3; ++c)
      longest = std::max(longest, (triangle[c] - triangle[(c + 1) % 3]).norm());
    if (longest > long_edge) {
      boxes.push_back(Box3::around(triangle).expanded(halo + longest));
    } else {
      corners.insert(corners.end(), triangle.begin(), triangle.end());
      longest_short = std::max(longest_short, longest);
    }
  }
  const double reach = halo + longest_short;
  const auto covering = covering_boxes(corners, 3.0 * reach, reach);
  boxes.insert(boxes.end(), covering.begin(), covering.end());
  return boxes;
}

/// This rank's seeds and the other ranks' within `halo` of its triangles. Collective.
SeedView seeds_near(const par::Comm& comm, const TriangleMesh& share,
                    std::span<const Vec3> run_seeds, std::span<const std::int64_t> run_ids,
                    std::span<const std::int64_t> seed_offsets, double halo) {
  const auto halo_seeds = exchange_point_halo(comm, run_ids, run_seeds, halo_boxes(share, halo));
  SeedView view;
  const std::int64_t first = seed_offsets[std::size_t(comm.rank)];
  for (std::size_t i = 0; i < run_seeds.size(); ++i) {
    view.positions.push_back(run_seeds[i]);
    view.ids.push_back(run_ids[i]);
    view.global.push_back(std::int32_t(first + std::int64_t(i)));
  }
  for (const HaloPoint& seed : halo_seeds) {
    view.positions.push_back(seed.position);
    view.ids.push_back(seed.id);
    view.global.push_back(std::int32_t(seed_offsets[std::size_t(seed.owner)] + seed.owner_index));
  }
  return view;
}

/// Every rank's seeds on every rank, in rank order. Collective.
SeedView every_seed(const par::Comm& comm, std::span<const Vec3> run_seeds,
                    std::span<const std::int64_t> run_ids,
                    std::span<const std::int64_t> seed_offsets) {
  SeedView all;
  const auto total = std::size_t(seed_offsets.back());
  const auto first = std::ptrdiff_t(seed_offsets[std::size_t(comm.rank)]);
  all.positions.resize(total);
  all.ids.resize(total);
  std::copy(run_seeds.begin(), run_seeds.end(), all.positions.begin() + first);
  std::copy(run_ids.begin(), run_ids.end(), all.ids.begin() + first);
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  par::allgather_runs(comm, seed_offsets, all.positions.data(), 3, MPI_DOUBLE);
  par::allgather_runs(comm, seed_offsets, all.ids.data(), 1, MPI_INT64_T);
  return all;
}

/// Every rank's seeds on rank 0, in rank order (nothing on the others). Collective.
SeedView seeds_on_root(const par::Comm& comm, std::span<const Vec3> run_seeds,
                       std::span<const std::int64_t> run_ids) {
  std::vector<std::array<double, 3>> mine;
  for (const Vec3& seed : run_seeds)
    mine.push_back({seed.x(), seed.y(), seed.z()});
  SeedView all;
  for (const auto& xyz : par::gather_to_root(comm, std::span<const std::array<double, 3>>(mine)))
    all.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  all.ids = par::gather_to_root(comm, run_ids);
  return all;
}

} // namespace

TriangleMesh restricted_delaunay(const TriangleMesh& surface, std::span<const Vec3> seeds,
                                 std::span<const std::int64_t> seed_ids,
                                 std::int32_t chunk_triangles) {
  const DualInput input = dual_input(surface, seeds, seed_ids, chunk_triangles);
  PieceOwners owners(surface, seeds.size(), input);
  owners.hand_over_orphans(seed_ids);
  return dual_mesh(surface, seeds, seed_ids, input, owners);
}

TriangleMesh restricted_delaunay(const par::Comm& comm, const TriangleMesh& root_surface,
                                 std::span<const Vec3> run_seeds,
                                 std::span<const std::int64_t> run_ids, double halo,
                                 std::int32_t chunk_triangles, SeedHaloReport* report) {
  TEXSIM_VERIFY(run_seeds.size() == run_ids.size(),
                "restricted_delaunay: " << run_seeds.size() << " seeds and " << run_ids.size()
                                        << " ids");
  const std::vector<std::int64_t> seed_offsets =
      par::run_offsets(comm, std::int64_t(run_seeds.size()));
  // The triangles along a Morton curve, so that each rank's run is a compact patch whose halo of
  // seeds is small; the result does not depend on the triangles' order.
  TriangleMesh curve;
  if (comm.is_root())
    curve = along_morton_curve(root_surface);
  const TriangleMesh share = triangles_from_root(comm, curve);
  // The pieces depend only on a triangle's corners and the seeds that clip them, so each rank's
  // are the bits the whole surface gives; rank 0 appends them in rank order, the serial order.
  DualInput mine;
  bool enough = true;
  SeedHaloReport cut_against;
  {
    const SeedView near = seeds_near(comm, share, run_seeds, run_ids, seed_offsets, halo);
    cut_against.seeds = std::int64_t(near.positions.size());
    try {
      mine = dual_input(share, near.positions, near.ids, chunk_triangles, near.global);
      enough = 3.0 * mine.largest_piece_radius <= halo;
    } catch (const Error&) {
      enough = false; // not certified with the halo's seeds; the retry below reports real errors
    }
  }
  int everywhere = enough ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &everywhere, 1, MPI_INT, MPI_MIN, comm.raw);
  if (everywhere == 0) {
    const SeedView all = every_seed(comm, run_seeds, run_ids, seed_offsets);
    cut_against = {std::int64_t(all.positions.size()), true};
    par::run_collectively(
        comm, [&] { mine = dual_input(share, all.positions, all.ids, chunk_triangles); });
  }
  if (report)
    *report = cut_against;
  const std::int64_t triangles = curve.num_triangles();
  DualInput input;
  std::vector<std::size_t> pair_run_ends; // each rank's pairs are sorted and unique
  std::vector<std::size_t> piece_begin;   // each rank's first piece in `input`
  KeptBorders kept;
  {
    std::vector<std::byte> bytes = serialize(mine);
    kept = keep_borders(mine);
    mine = DualInput();
    reserve_for_parts(comm, bytes, input);
    par::stream_to_root(comm, bytes, [&](int rank, std::span<const std::byte> part) {
      piece_begin.push_back(input.pieces.size());
      append(part, std::int32_t(par::even_run_begin(triangles, rank, comm.size)), input);
      pair_run_ends.push_back(input.neighbour_pairs.size());
    });
  } // rank 0's own serialized part is gone before the join
  merge_sorted_runs(input.neighbour_pairs, std::move(pair_run_ends));
  const SeedView all_on_root = seeds_on_root(comm, run_seeds, run_ids);
  std::optional<PieceOwners> owners;
  par::run_collectively(comm, [&] {
    if (comm.is_root())
      owners.emplace(curve, all_on_root.positions.size(), input);
  });
  fetch_orphan_borders(comm,
                       owners ? std::span<const std::size_t>(owners->orphan_pieces())
                              : std::span<const std::size_t>(),
                       piece_begin, kept, input);
  kept = KeptBorders();
  TriangleMesh mesh;
  par::run_collectively(comm, [&] {
    if (comm.is_root()) {
      owners->hand_over_orphans(all_on_root.ids);
      mesh = dual_mesh(curve, all_on_root.positions, all_on_root.ids, input, *owners);
    }
  });
  return mesh;
}

} // namespace texsim::geom
