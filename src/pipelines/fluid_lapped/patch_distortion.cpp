#include "pipelines/fluid_lapped/patch_distortion.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace texsim::pipelines::fluid_lapped {

double triangle_distortion(const std::array<Eigen::Vector2d, 3>& rest,
                           const std::array<geom::Vec3, 3>& current) {
  constexpr double infinity = std::numeric_limits<double>::infinity();
  Eigen::Matrix2d r;
  r.col(0) = rest[1] - rest[0];
  r.col(1) = rest[2] - rest[0];
  const geom::Vec3 a = current[1] - current[0], b = current[2] - current[0];
  const geom::Vec3 normal = a.cross(b);
  const double scale = std::max(r.cwiseAbs().maxCoeff(), a.norm() + b.norm());
  if (std::abs(r.determinant()) <= 1e-14 * scale * scale || normal.norm() <= 1e-14 * scale * scale)
    return infinity;
  // The current triangle in an orthonormal frame of its own plane.
  const geom::Vec3 e1 = a.normalized(), e2 = normal.cross(a).normalized();
  Eigen::Matrix2d c;
  c << a.norm(), e1.dot(b), 0.0, e2.dot(b);
  const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(c * r.inverse()).singularValues();
  return s[1] > 0 ? std::max(s[0], 1.0 / s[1]) : infinity;
}

double triangle_quality(double delta, double delta_max) {
  return std::max((delta_max - delta) / (delta_max - 1.0), 0.0);
}

void update_weights(Patch& patch, double radius, double delta_max) {
  const auto n = patch.positions.size();
  std::vector<double> quality_sum(n, 0.0);
  std::vector<int> triangle_count(n, 0);
  // Edges used by one triangle are the boundary; their vertices are boundary vertices.
  std::map<std::pair<std::int32_t, std::int32_t>, int> edge_uses;
  for (const auto& t : patch.triangles) {
    std::array<Eigen::Vector2d, 3> rest;
    std::array<geom::Vec3, 3> current;
    for (int c = 0; c < 3; ++c) {
      rest[std::size_t(c)] = patch.rest_uv[std::size_t(t[std::size_t(c)])] * (2.0 * radius);
      current[std::size_t(c)] = patch.positions[std::size_t(t[std::size_t(c)])];
      const auto u = t[std::size_t(c)], v = t[std::size_t((c + 1) % 3)];
      ++edge_uses[{std::min(u, v), std::max(u, v)}];
    }
    const double quality = triangle_quality(triangle_distortion(rest, current), delta_max);
    for (const auto v : t) {
      quality_sum[std::size_t(v)] += quality;
      ++triangle_count[std::size_t(v)];
    }
  }
  std::vector<bool> boundary(n, false);
  for (const auto& [edge, uses] : edge_uses)
    if (uses == 1)
      boundary[std::size_t(edge.first)] = boundary[std::size_t(edge.second)] = true;
  const Eigen::Vector2d centre(0.5, 0.5);
  // The corners of the triangle holding p keep B_V = 1 even when farther than r / 4 (coarse
  // triangles): the paper's reason for case 2 is that p itself must never be eroded.
  std::vector<bool> holds_p(n, false);
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  for (const auto& t : patch.triangles) {
    const auto& a = patch.rest_uv[std::size_t(t[0])];
    const auto& b = patch.rest_uv[std::size_t(t[1])];
    const auto& c = patch.rest_uv[std::size_t(t[2])];
    const double area = cross(b - a, c - a);
    const double s0 = cross(b - centre, c - centre) / area,
                 s1 = cross(c - centre, a - centre) / area;
    if (area != 0 && s0 >= 0 && s1 >= 0 && 1 - s0 - s1 >= 0)
      for (const auto v : t)
        holds_p[std::size_t(v)] = true;
  }
  patch.weights.assign(n, 0.0);
  for (std::size_t v = 0; v < n; ++v) {
    if (triangle_count[v] == 0)
      continue;
    const bool far_boundary = boundary[v] && !holds_p[v] &&
                              (patch.rest_uv[v] - centre).norm() * 2.0 * radius > radius / 4.0;
    patch.weights[v] = far_boundary ? 0.0 : quality_sum[v] / triangle_count[v];
  }
}

} // namespace texsim::pipelines::fluid_lapped
