#include "geom/surface_walker.hpp"

#include "core/error.hpp"

#include <Eigen/Geometry>

#include <algorithm>

namespace texsim::geom {
namespace {

using Bary = std::array<double, 3>;

// Clamps rounding-level negatives to zero and renormalises so the weights sum to one.
void clamp_to_triangle(Bary& lambda) {
  double sum = 0.0;
  for (double& l : lambda) {
    l = std::max(l, 0.0);
    sum += l;
  }
  if (sum > 0.0) {
    for (double& l : lambda)
      l /= sum;
  } else {
    lambda = {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
  }
}

// Unit vector in the plane of (a, b, opposite), perpendicular to the edge direction `edge`
// (unit) and pointing from the edge towards `opposite`.
Vec3 inward_normal(const Vec3& a, const Vec3& edge, const Vec3& opposite) {
  const Vec3 to_opposite = opposite - a;
  return (to_opposite - edge * edge.dot(to_opposite)).normalized();
}

} // namespace

SurfaceWalker::SurfaceWalker(const TriangleMesh& mesh, const MeshTopology& topology) {
  TEXSIM_VERIFY(topology.num_triangles() == mesh.num_triangles(),
                "SurfaceWalker: topology has " << topology.num_triangles()
                                               << " triangles, the mesh " << mesh.num_triangles());
  faces_.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < faces_.size(); ++t) {
    Face& f = faces_[t];
    for (int c = 0; c < 3; ++c) {
      f.vertex[c] = mesh.triangles[t][c];
      f.corner[c] = mesh.positions[f.vertex[c]];
    }
    const Vec3 e1 = f.corner[1] - f.corner[0];
    const Vec3 e2 = f.corner[2] - f.corner[0];
    const double d11 = e1.squaredNorm(), d12 = e1.dot(e2), d22 = e2.squaredNorm();
    const double det = d11 * d22 - d12 * d12;
    // det = |e1|^2 |e2|^2 sin^2(angle): a relative test so that tiny but well-shaped triangles
    // still count.
    f.wall = !(det > 1e-14 * d11 * d22) || d11 == 0.0 || d22 == 0.0;
    if (!f.wall) {
      // lambda_1 = grad1 . (x - corner0) and lambda_2 = grad2 . (x - corner0) for x in the plane.
      f.grad1 = (d22 * e1 - d12 * e2) / det;
      f.grad2 = (d11 * e2 - d12 * e1) / det;
      f.normal = e1.cross(e2).normalized();
    }
  }
  for (std::size_t t = 0; t < faces_.size(); ++t) {
    Face& f = faces_[t];
    if (f.wall)
      continue;
    for (int c = 0; c < 3; ++c) {
      const auto incident = topology.edge_triangles(topology.triangle_edges(t)[c]);
      if (incident.size() != 2)
        continue;
      const std::int32_t other = incident[0] == std::int32_t(t) ? incident[1] : incident[0];
      if (other == std::int32_t(t) || faces_[other].wall)
        continue;
      const auto& other_edges = topology.triangle_edges(other);
      for (int k = 0; k < 3; ++k)
        if (other_edges[k] == topology.triangle_edges(t)[c]) {
          f.neighbor[c] = other;
          f.neighbor_corner[c] = static_cast<std::int8_t>(k);
        }
    }
  }
}

std::array<double, 3> SurfaceWalker::barycentric(std::int32_t triangle,
                                                 const Vec3& position) const {
  const Face& f = faces_[triangle];
  if (f.wall)
    return {0.0, 0.0, 0.0};
  const Vec3 offset = position - f.corner[0];
  const double l1 = f.grad1.dot(offset), l2 = f.grad2.dot(offset);
  return {1.0 - l1 - l2, l1, l2};
}

SurfacePoint SurfaceWalker::move(const SurfacePoint& p, const Vec3& displacement) const {
  TEXSIM_ASSERT(p.triangle >= 0 && p.triangle < num_triangles(),
                "SurfaceWalker::move: triangle " << p.triangle << " out of range");
  std::int32_t t = p.triangle;
  const Face* f = &faces_[t];
  if (f->wall)
    return p;
  Bary lambda = barycentric(t, p.position);
  clamp_to_triangle(lambda);
  Vec3 rest = displacement - f->normal * f->normal.dot(displacement);
  int entry = -1; // corner opposite the edge the path came in through
  for (int crossing = 0;; ++crossing) {
    const double g1 = f->grad1.dot(rest), g2 = f->grad2.dot(rest);
    const Bary change{-(g1 + g2), g1, g2};
    // The first edge the path reaches: the smallest fraction s of `rest` at which a coordinate
    // turns negative. The entry edge is skipped: the path leaves it, rounding aside.
    int exit = -1;
    double s_exit = 1.0;
    for (int c = 0; c < 3; ++c) {
      if (c == entry || change[c] >= 0.0 || lambda[c] + change[c] >= 0.0)
        continue;
      const double s = std::max(lambda[c], 0.0) / -change[c];
      if (s < s_exit) {
        s_exit = s;
        exit = c;
      }
    }
    if (exit < 0) {
      for (int c = 0; c < 3; ++c)
        lambda[c] += change[c];
      clamp_to_triangle(lambda);
      break;
    }
    for (int c = 0; c < 3; ++c)
      lambda[c] += s_exit * change[c];
    lambda[exit] = 0.0;
    clamp_to_triangle(lambda);
    const std::int32_t next = f->neighbor[exit];
    if (next < 0 || crossing == kMaxCrossings)
      break; // boundary, non-manifold edge or wall: stop on the edge
    const Face& g = faces_[next];
    const int next_corner = f->neighbor_corner[exit];
    // Unfold: keep the component along the shared edge, turn the component leaving f into
    // the same amount entering g.
    const int a = (exit + 1) % 3, b = (exit + 2) % 3;
    const Vec3 edge = (f->corner[b] - f->corner[a]).normalized();
    const Vec3 into_f = inward_normal(f->corner[a], edge, f->corner[exit]);
    const Vec3 into_g = inward_normal(f->corner[a], edge, g.corner[next_corner]);
    rest *= 1.0 - s_exit;
    rest = edge * edge.dot(rest) - into_g * into_f.dot(rest);
    // The crossing point keeps its weights on the two shared vertices.
    Bary next_lambda{0.0, 0.0, 0.0};
    for (int c = 0; c < 3; ++c) {
      if (c == next_corner)
        continue;
      next_lambda[c] = g.vertex[c] == f->vertex[a] ? lambda[a] : lambda[b];
    }
    lambda = next_lambda;
    t = next;
    f = &g;
    entry = next_corner;
  }
  SurfacePoint result;
  result.triangle = t;
  result.position = lambda[0] * f->corner[0] + lambda[1] * f->corner[1] + lambda[2] * f->corner[2];
  return result;
}

} // namespace texsim::geom
