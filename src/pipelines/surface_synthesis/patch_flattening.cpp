#include "pipelines/surface_synthesis/patch_flattening.hpp"

#include "core/error.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace texsim::pipelines::surface_synthesis {
namespace {

using Corners = std::array<Eigen::Vector2d, 3>;

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

double signed_area2(const Corners& c) {
  return cross(c[1] - c[0], c[2] - c[0]);
}

/// Squared distance from the origin to the segment [a, b].
double origin_segment_distance2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double along = length2 > 0.0 ? std::clamp(-a.dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + along * ab).squaredNorm();
}

/// Distance from the origin to a positively oriented flattened triangle (0 when it contains it).
double origin_distance(const Corners& c) {
  bool inside = true;
  for (int i = 0; i < 3; ++i) {
    inside = inside && cross(c[(i + 1) % 3] - c[i], -c[i]) >= 0.0;
  }
  if (inside) {
    return 0.0;
  }
  return std::sqrt(
      std::min({origin_segment_distance2(c[0], c[1]), origin_segment_distance2(c[1], c[2]),
                origin_segment_distance2(c[2], c[0])}));
}

/// The triangle's normal leans away from n by 90 degrees or more: the surface folds back.
bool folds_away(const geom::TriangleMesh& mesh, std::int32_t triangle, const geom::Vec3& n) {
  const auto& v = mesh.triangles[triangle];
  const geom::Vec3& a = mesh.positions[v[0]];
  const geom::Vec3 normal = (mesh.positions[v[1]] - a).cross(mesh.positions[v[2]] - a);
  return !(normal.dot(n) > 0.0);
}

/// Position of the corner opposite the flattened edge (a, b) at 3D distances to_a and to_b from
/// its ends, on the side of the edge away from `away`; false when no such triangle exists.
bool unfold_corner(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& away,
                   double to_a, double to_b, Eigen::Vector2d& corner) {
  const Eigen::Vector2d edge = b - a;
  const double length = edge.norm();
  if (!(length > 0.0)) {
    return false;
  }
  const Eigen::Vector2d along = edge / length;
  const double x = (length * length + to_a * to_a - to_b * to_b) / (2.0 * length);
  const double height2 = to_a * to_a - x * x;
  if (!(height2 > 0.0)) {
    return false;
  }
  Eigen::Vector2d across(-along.y(), along.x());
  if (across.dot(away - a) > 0.0) {
    across = -across;
  }
  corner = a + x * along + std::sqrt(height2) * across;
  return true;
}

} // namespace

void flatten_patch(const geom::TriangleMesh& mesh, const geom::MeshTopology& topology,
                   std::span<const std::int32_t> seed_triangles, const TangentFrame& frame,
                   double radius, FlattenedPatch& out, PatchScratch& scratch) {
  using Candidate = PatchScratch::Candidate;
  out.triangles.clear();
  out.vertices.clear();
  out.corners.clear();
  if (scratch.triangle_mark.size() != static_cast<std::size_t>(mesh.num_triangles()) ||
      scratch.vertex_mark.size() != static_cast<std::size_t>(mesh.num_vertices()) ||
      ++scratch.call_id == 0) {
    // New mesh or the call counter wrapped: forget every mark.
    scratch.triangle_mark.assign(static_cast<std::size_t>(mesh.num_triangles()), 0);
    scratch.vertex_mark.assign(static_cast<std::size_t>(mesh.num_vertices()), 0);
    scratch.vertex_position.resize(static_cast<std::size_t>(mesh.num_vertices()));
    scratch.call_id = 1;
  }
  const std::uint32_t call_id = scratch.call_id;
  auto& triangle_done = scratch.triangle_mark;
  const auto placed = [&](std::int32_t v) { return scratch.vertex_mark[v] == call_id; };
  const auto& position = scratch.vertex_position;
  auto& heap = scratch.heap;
  heap.clear();
  const auto later = [](const Candidate& x, const Candidate& y) { return y.key() < x.key(); };
  const auto push = [&](const Candidate& candidate) {
    heap.push_back(candidate);
    std::push_heap(heap.begin(), heap.end(), later);
  };

  const auto add = [&](std::int32_t triangle, const Corners& corners) {
    triangle_done[triangle] = call_id;
    for (int i = 0; i < 3; ++i) {
      const std::int32_t v = mesh.triangles[triangle][i];
      scratch.vertex_mark[v] = call_id;
      scratch.vertex_position[v] = corners[i];
    }
    out.triangles.push_back(triangle);
    out.vertices.push_back(mesh.triangles[triangle]);
    out.corners.push_back(corners);
  };
  for (const std::int32_t seed : seed_triangles) {
    TEXSIM_ASSERT(seed >= 0 && seed < mesh.num_triangles(),
                  "seed triangle " << seed << " of " << mesh.num_triangles());
    if (triangle_done[seed] == call_id || folds_away(mesh, seed, frame.n)) {
      continue;
    }
    Corners corners;
    for (int i = 0; i < 3; ++i) {
      const geom::Vec3 r = mesh.positions[mesh.triangles[seed][i]] - frame.origin;
      corners[i] = Eigen::Vector2d(r.dot(frame.s), r.dot(frame.t));
    }
    if (signed_area2(corners) > 0.0) {
      add(seed, corners);
    }
  }

  // Corners of `triangle` with its corner `opposite` at `far_position`, the others where placed.
  const auto corners_with = [&](std::int32_t triangle, int opposite,
                                const Eigen::Vector2d& far_position) {
    Corners corners;
    for (int k = 0; k < 3; ++k) {
      corners[k] = k == opposite ? far_position : position[mesh.triangles[triangle][k]];
    }
    return corners;
  };

  // Offers every triangle across an edge of patch triangle `parent` that is still open.
  const auto offer_neighbours = [&](std::int32_t parent) {
    const std::int32_t triangle = out.triangles[parent];
    for (int corner = 0; corner < 3; ++corner) {
      // The edge opposite `corner` joins vertices a and b.
      const std::int32_t a = out.vertices[parent][(corner + 1) % 3];
      const std::int32_t b = out.vertices[parent][(corner + 2) % 3];
      const std::int32_t edge = topology.triangle_edges(triangle)[corner];
      for (const std::int32_t next : topology.edge_triangles(edge)) {
        if (triangle_done[next] == call_id) {
          continue;
        }
        if (folds_away(mesh, next, frame.n)) {
          triangle_done[next] = call_id;
          continue;
        }
        // folds_away() has rejected triangles with a repeated vertex (zero normal), so `next`
        // has exactly one corner besides a and b.
        const auto& w = mesh.triangles[next];
        int opposite = 0;
        while (w[opposite] == a || w[opposite] == b) {
          ++opposite;
        }
        const std::int32_t c = w[opposite];
        Eigen::Vector2d far_position;
        if (placed(c)) {
          far_position = position[c];
        } else {
          const geom::Vec3& far = mesh.positions[c];
          if (!unfold_corner(position[a], position[b], out.corners[parent][corner],
                             (far - mesh.positions[a]).norm(), (far - mesh.positions[b]).norm(),
                             far_position)) {
            continue;
          }
        }
        const Corners corners = corners_with(next, opposite, far_position);
        if (!(signed_area2(corners) > 0.0)) {
          // Flipped between placed vertices (every path gives these corners), or an unfolding
          // that came out flipped through inconsistently oriented neighbours.
          if (placed(c)) {
            triangle_done[next] = call_id;
          }
          continue;
        }
        const Candidate candidate{origin_distance(corners), next, parent, opposite, far_position};
        if (candidate.distance <= radius) {
          push(candidate);
        }
      }
    }
  };

  const auto seeds = static_cast<std::int32_t>(out.triangles.size());
  for (std::int32_t parent = 0; parent < seeds; ++parent) {
    offer_neighbours(parent);
  }
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), later);
    const Candidate candidate = heap.back();
    heap.pop_back();
    if (triangle_done[candidate.triangle] == call_id) {
      continue;
    }
    const std::int32_t c = mesh.triangles[candidate.triangle][candidate.opposite];
    if (placed(c) && position[c] != candidate.far_position) {
      // The far vertex was placed by another triangle since this candidate was offered: the
      // patch keeps one position per vertex (no cracks where growth fronts meet), so the
      // candidate is judged again with that position.
      const Corners corners = corners_with(candidate.triangle, candidate.opposite, position[c]);
      if (!(signed_area2(corners) > 0.0)) {
        triangle_done[candidate.triangle] = call_id;
        continue;
      }
      const Candidate again{origin_distance(corners), candidate.triangle, candidate.parent,
                            candidate.opposite, position[c]};
      if (again.distance <= radius) {
        push(again);
      }
      continue;
    }
    add(candidate.triangle,
        corners_with(candidate.triangle, candidate.opposite, candidate.far_position));
    offer_neighbours(static_cast<std::int32_t>(out.triangles.size()) - 1);
  }
}

void sample_patch(const FlattenedPatch& patch, std::span<const Eigen::Vector2d> positions,
                  std::span<SampleWeights> out) {
  TEXSIM_VERIFY(out.size() == positions.size(), "sample_patch: " << out.size() << " outputs for "
                                                                 << positions.size()
                                                                 << " positions");
  constexpr double kTolerance = 1e-12;
  for (std::size_t s = 0; s < positions.size(); ++s) {
    const Eigen::Vector2d& q = positions[s];
    out[s] = SampleWeights{};
    for (std::size_t k = 0; k < patch.triangles.size(); ++k) {
      const Corners& c = patch.corners[k];
      const double area2 = signed_area2(c);
      // w_i: area of the sub-triangle opposite corner i, relative to the whole (scaled by area2
      // until the sample is known to be inside).
      std::array<double, 3> w{};
      bool inside = true;
      for (int i = 0; i < 3 && inside; ++i) {
        w[i] = cross(c[(i + 2) % 3] - c[(i + 1) % 3], q - c[(i + 1) % 3]);
        inside = w[i] >= -kTolerance * area2;
      }
      if (!inside) {
        continue;
      }
      for (double& weight : w) {
        weight = std::max(weight, 0.0);
      }
      const double sum = w[0] + w[1] + w[2];
      for (double& weight : w) {
        weight /= sum;
      }
      for (int i = 0; i < 3; ++i)
        out[s].weights[std::size_t(i)] = float(w[i]);
      out[s].vertices = patch.vertices[k];
      break;
    }
  }
}

} // namespace texsim::pipelines::surface_synthesis
