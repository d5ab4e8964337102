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

/// Distance from the origin to the segment [a, b].
double origin_segment_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double along = length2 > 0.0 ? std::clamp(-a.dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + along * ab).norm();
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
  double distance = origin_segment_distance(c[0], c[1]);
  distance = std::min(distance, origin_segment_distance(c[1], c[2]));
  return std::min(distance, origin_segment_distance(c[2], c[0]));
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
  auto& mark = scratch.mark;
  if (mark.size() != static_cast<std::size_t>(mesh.num_triangles()) || ++scratch.call_id == 0) {
    // New mesh or the call counter wrapped: forget every mark.
    mark.assign(static_cast<std::size_t>(mesh.num_triangles()), 0);
    scratch.call_id = 1;
  }
  const std::uint32_t call_id = scratch.call_id;
  auto& heap = scratch.heap;
  heap.clear();
  const auto later = [](const Candidate& x, const Candidate& y) { return y.key() < x.key(); };
  const auto flatten = [&](const geom::Vec3& p) {
    const geom::Vec3 r = p - frame.origin;
    return Eigen::Vector2d(r.dot(frame.s), r.dot(frame.t));
  };

  const auto add = [&](std::int32_t triangle, const Corners& corners) {
    mark[triangle] = call_id;
    out.triangles.push_back(triangle);
    out.vertices.push_back(mesh.triangles[triangle]);
    out.corners.push_back(corners);
  };
  for (const std::int32_t seed : seed_triangles) {
    TEXSIM_ASSERT(seed >= 0 && seed < mesh.num_triangles(),
                  "seed triangle " << seed << " of " << mesh.num_triangles());
    if (mark[seed] == call_id || folds_away(mesh, seed, frame.n)) {
      continue;
    }
    const auto& v = mesh.triangles[seed];
    const Corners corners{flatten(mesh.positions[v[0]]), flatten(mesh.positions[v[1]]),
                          flatten(mesh.positions[v[2]])};
    if (signed_area2(corners) > 0.0) {
      add(seed, corners);
    }
  }

  // Offers every unmarked triangle across an edge of patch triangle `parent` as a candidate.
  const auto offer_neighbours = [&](std::int32_t parent) {
    const std::int32_t triangle = out.triangles[parent];
    const Corners& corners = out.corners[parent];
    for (int corner = 0; corner < 3; ++corner) {
      // The edge opposite `corner` joins corners i and j.
      const int i = (corner + 1) % 3, j = (corner + 2) % 3;
      const std::int32_t vi = mesh.triangles[triangle][i], vj = mesh.triangles[triangle][j];
      for (const std::int32_t next :
           topology.edge_triangles(topology.triangle_edges(triangle)[corner])) {
        if (mark[next] == call_id) {
          continue;
        }
        if (folds_away(mesh, next, frame.n)) {
          mark[next] = call_id;
          continue;
        }
        const auto& w = mesh.triangles[next];
        Candidate candidate{0.0, next, parent, {}};
        int opposite = -1;
        for (int k = 0; k < 3; ++k) {
          if (w[k] == vi) {
            candidate.corners[k] = corners[i];
          } else if (w[k] == vj) {
            candidate.corners[k] = corners[j];
          } else {
            opposite = k;
          }
        }
        const geom::Vec3& far = mesh.positions[w[opposite]];
        if (!unfold_corner(corners[i], corners[j], corners[corner],
                           (far - mesh.positions[vi]).norm(), (far - mesh.positions[vj]).norm(),
                           candidate.corners[opposite]) ||
            !(signed_area2(candidate.corners) > 0.0)) {
          continue;
        }
        candidate.distance = origin_distance(candidate.corners);
        if (candidate.distance <= radius) {
          heap.push_back(candidate);
          std::push_heap(heap.begin(), heap.end(), later);
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
    if (mark[candidate.triangle] == call_id) {
      continue;
    }
    add(candidate.triangle, candidate.corners);
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
      // w_i: area of the sub-triangle opposite corner i, relative to the whole.
      std::array<double, 3> w{};
      bool inside = true;
      for (int i = 0; i < 3 && inside; ++i) {
        w[i] = cross(c[(i + 2) % 3] - c[(i + 1) % 3], q - c[(i + 1) % 3]) / area2;
        inside = w[i] >= -kTolerance;
      }
      if (!inside) {
        continue;
      }
      for (double& weight : w) {
        weight = std::clamp(weight, 0.0, 1.0);
      }
      const double sum = w[0] + w[1] + w[2];
      for (double& weight : w) {
        weight /= sum;
      }
      out[s].weights = w;
      out[s].vertices = patch.vertices[k];
      break;
    }
  }
}

} // namespace texsim::pipelines::surface_synthesis
