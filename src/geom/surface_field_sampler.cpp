#include "geom/surface_field_sampler.hpp"

#include "core/error.hpp"

namespace texsim::geom {

SurfaceFieldSampler::SurfaceFieldSampler(const TriangleMesh& mesh,
                                         std::vector<std::vector<double>> values)
    : mesh_(mesh), values_(std::move(values)), tree_(mesh) {
  for (const auto& field : values_)
    TEXSIM_VERIFY(field.size() == mesh_.positions.size(),
                  "field with " << field.size() << " values on " << mesh_.positions.size()
                                << " vertices");
}

std::vector<double> SurfaceFieldSampler::sample(std::size_t k, std::span<const Vec3> points) const {
  TEXSIM_VERIFY(k < values_.size(), "field " << k << " of " << values_.size());
  const auto& field = values_[k];
  std::vector<double> result(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto closest = tree_.closest_point(points[i]);
    const auto& t = mesh_.triangles[std::size_t(closest.triangle)];
    const Vec3& a = mesh_.positions[std::size_t(t[0])];
    const Vec3 e1 = mesh_.positions[std::size_t(t[1])] - a;
    const Vec3 e2 = mesh_.positions[std::size_t(t[2])] - a;
    const Vec3 d = closest.point - a;
    // Barycentric coordinates from the 2x2 normal equations of d = u e1 + v e2.
    const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
    const double det = g11 * g22 - g12 * g12;
    const double d1 = d.dot(e1), d2 = d.dot(e2);
    const double u = det > 0 ? (g22 * d1 - g12 * d2) / det : 0.0;
    const double v = det > 0 ? (g11 * d2 - g12 * d1) / det : 0.0;
    result[i] = (1 - u - v) * field[std::size_t(t[0])] + u * field[std::size_t(t[1])] +
                v * field[std::size_t(t[2])];
  }
  return result;
}

} // namespace texsim::geom
