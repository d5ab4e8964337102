#include "pipelines/fluid_lapped/patch_advection.hpp"

#include <algorithm>
#include <cmath>

namespace texsim::pipelines::fluid_lapped {

void advect_patch(Patch& patch, const VelocityField& velocity, double t0, double t1,
                  const AdvectionSettings& settings) {
  const double span = t1 - t0;
  const auto count = std::int64_t(patch.positions.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t v = 0; v < count; ++v) {
    geom::Vec3 x = patch.positions[std::size_t(v)];
    const double travel = velocity.at(x, t0).norm() * std::abs(span);
    const int steps =
        settings.substep_multiplier *
        std::max(1, int(std::ceil(settings.max_step_length > 0 ? travel / settings.max_step_length
                                                               : 1.0)));
    const double h = span / steps;
    for (int s = 0; s < steps; ++s) {
      const double t = t0 + s * h;
      const geom::Vec3 k1 = velocity.at(x, t);
      const geom::Vec3 k2 = velocity.at(x + 0.5 * h * k1, t + 0.5 * h);
      const geom::Vec3 k3 = velocity.at(x + 0.5 * h * k2, t + 0.5 * h);
      const geom::Vec3 k4 = velocity.at(x + h * k3, t + h);
      x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    patch.positions[std::size_t(v)] = x;
  }
}

void project_patch(Patch& patch, const FrameSurface& next, double radius) {
  const auto n = patch.positions.size();
  std::vector<char> kept(n); // not vector<bool>: threads write neighbouring entries
#pragma omp parallel for schedule(static)
  for (std::int64_t v = 0; v < std::int64_t(n); ++v) {
    const auto closest = next.tree.closest_point(patch.positions[std::size_t(v)]);
    kept[std::size_t(v)] = closest.distance <= radius / 4.0;
    patch.positions[std::size_t(v)] = closest.point;
    patch.surface_triangle[std::size_t(v)] = closest.triangle;
  }
  std::erase_if(patch.triangles, [&](const geom::Triangle& t) {
    return !kept[std::size_t(t[0])] || !kept[std::size_t(t[1])] || !kept[std::size_t(t[2])];
  });
  std::vector<std::int32_t> renumber(n, -1);
  for (const auto& t : patch.triangles)
    for (const auto v : t)
      renumber[std::size_t(v)] = 0;
  std::int32_t next_index = 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (renumber[v] < 0)
      continue;
    renumber[v] = next_index;
    patch.positions[std::size_t(next_index)] = patch.positions[v];
    patch.surface_triangle[std::size_t(next_index)] = patch.surface_triangle[v];
    patch.rest_uv[std::size_t(next_index)] = patch.rest_uv[v];
    patch.weights[std::size_t(next_index)] = patch.weights[v];
    ++next_index;
  }
  patch.positions.resize(std::size_t(next_index));
  patch.surface_triangle.resize(std::size_t(next_index));
  patch.rest_uv.resize(std::size_t(next_index));
  patch.weights.resize(std::size_t(next_index));
  for (auto& t : patch.triangles)
    for (auto& v : t)
      v = renumber[std::size_t(v)];
}

} // namespace texsim::pipelines::fluid_lapped
