#include "geom/restricted_delaunay.hpp"

#include "geom/mesh_topology.hpp"
#include "geom/restricted_voronoi.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
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

/// A corner of a piece between two bisector edges: the cells of the piece's seed and of the two
/// labels meet there.
struct Meeting {
  std::int32_t piece;
  std::int32_t corner;
};

/// Seeds whose cells share a border (of any length) somewhere on the surface, per seed.
CsrAdjacency voronoi_neighbours(const std::vector<VoronoiPiece>& pieces, std::size_t num_seeds) {
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  for (const VoronoiPiece& piece : pieces)
    for (const std::int32_t label : piece.edge_labels)
      if (label >= 0) {
        pairs.emplace_back(piece.seed, label);
        pairs.emplace_back(label, piece.seed);
      }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  CsrAdjacency adjacency;
  adjacency.offsets.assign(num_seeds + 1, 0);
  for (const auto& [from, to] : pairs) {
    ++adjacency.offsets[std::size_t(from) + 1];
    adjacency.indices.push_back(to);
  }
  std::partial_sum(adjacency.offsets.begin(), adjacency.offsets.end(), adjacency.offsets.begin());
  return adjacency;
}

class MeetingTriangulator {
public:
  MeetingTriangulator(const TriangleMesh& surface, std::span<const Vec3> seeds,
                      std::span<const std::int64_t> seed_ids,
                      const std::vector<VoronoiPiece>& pieces)
      : surface_(surface), seeds_(seeds), ids_(seed_ids), pieces_(pieces),
        neighbours_(voronoi_neighbours(pieces, seeds.size())) {}

  /// The triangles of one meeting, counter-clockwise: (seed, a, b) when exactly three cells meet
  /// there, else the fan of every meeting seed from the smallest id.
  std::vector<Triangle> triangles(const Meeting& meeting) const {
    const VoronoiPiece& piece = pieces_[std::size_t(meeting.piece)];
    const std::size_t n = piece.polygon.size();
    const std::size_t k = std::size_t(meeting.corner);
    const std::int32_t i = piece.seed;
    const std::int32_t a = piece.edge_labels[(k + n - 1) % n];
    const std::int32_t b = piece.edge_labels[k];
    const Vec3& point = piece.polygon[k];
    std::vector<std::int32_t> meeting_seeds = seeds_meeting_at(point, i, a, b);
    if (meeting_seeds.size() == 3)
      return {Triangle{i, a, b}};
    order_around(point, piece.triangle, meeting_seeds);
    std::vector<Triangle> fan;
    for (std::size_t s = 1; s + 1 < meeting_seeds.size(); ++s)
      fan.push_back({meeting_seeds[0], meeting_seeds[s], meeting_seeds[s + 1]});
    return fan;
  }

private:
  /// i, a, b and every neighbour of theirs as far from `point` as i within the tolerance; a seed
  /// that borders none of the three cells cannot meet them there.
  std::vector<std::int32_t> seeds_meeting_at(const Vec3& point, std::int32_t i, std::int32_t a,
                                             std::int32_t b) const {
    const double reference = squared_distance(point, seeds_[std::size_t(i)]);
    const double r = std::sqrt(reference);
    const double tolerance = kMeetingTolerance * (point.cwiseAbs().maxCoeff() + r) * r;
    std::vector<std::int32_t> result = {i, a, b};
    for (const std::int32_t cell : {i, a, b})
      for (const std::int32_t c : neighbours_.row(cell))
        if (std::abs(squared_distance(point, seeds_[std::size_t(c)]) - reference) <= tolerance)
          result.push_back(c);
    std::sort(result.begin(), result.end());
    result.erase(std::unique(result.begin(), result.end()), result.end());
    return result;
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
  const std::vector<VoronoiPiece>& pieces_;
  CsrAdjacency neighbours_;
};

/// One sighting of a triangle: its vertices in increasing id order and whether it was seen in that
/// cyclic order (+1) or the other (-1).
struct Sighting {
  std::array<std::int64_t, 3> ids;
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
  return {{seed_ids[std::size_t(sorted[0])], seed_ids[std::size_t(sorted[1])],
           seed_ids[std::size_t(sorted[2])]},
          sorted,
          same_cycle ? 1 : -1};
}

} // namespace

TriangleMesh restricted_delaunay(const TriangleMesh& surface, std::span<const Vec3> seeds,
                                 std::span<const std::int64_t> seed_ids) {
  std::vector<std::int32_t> all_triangles(std::size_t(surface.num_triangles()));
  std::iota(all_triangles.begin(), all_triangles.end(), 0);
  const std::vector<VoronoiPiece> pieces =
      restricted_voronoi_pieces(surface, all_triangles, seeds, seed_ids, true);

  std::vector<Meeting> meetings;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const auto& labels = pieces[p].edge_labels;
    const std::size_t n = labels.size();
    for (std::size_t k = 0; k < n; ++k) {
      const std::int32_t before = labels[(k + n - 1) % n], after = labels[k];
      // Equal labels: a border split in two by a round-off re-entry, not a meeting.
      if (before >= 0 && after >= 0 && before != after)
        meetings.push_back({std::int32_t(p), std::int32_t(k)});
    }
  }

  const MeetingTriangulator triangulator(surface, seeds, seed_ids, pieces);
  std::vector<std::vector<Triangle>> found(meetings.size());
  const auto count = static_cast<std::int64_t>(meetings.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t m = 0; m < count; ++m)
    found[std::size_t(m)] = triangulator.triangles(meetings[std::size_t(m)]);

  std::vector<Sighting> sightings;
  for (const auto& triangles : found)
    for (const Triangle& t : triangles)
      sightings.push_back(sighting_of(t, seed_ids));
  std::sort(sightings.begin(), sightings.end(),
            [](const Sighting& x, const Sighting& y) { return x.ids < y.ids; });

  TriangleMesh mesh;
  mesh.positions.assign(seeds.begin(), seeds.end());
  for (std::size_t s = 0; s < sightings.size();) {
    int votes = 0;
    std::size_t end = s;
    for (; end < sightings.size() && sightings[end].ids == sightings[s].ids; ++end)
      votes += sightings[end].vote;
    const Triangle& v = sightings[s].vertices;
    mesh.triangles.push_back(votes >= 0 ? v : Triangle{v[0], v[2], v[1]});
    s = end;
  }
  return mesh;
}

} // namespace texsim::geom
