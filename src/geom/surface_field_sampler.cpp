#include "geom/surface_field_sampler.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"

#include <algorithm>

namespace texsim::geom {

SurfaceFieldSampler::SurfaceFieldSampler(const TriangleMesh& mesh,
                                         std::vector<std::vector<double>> values)
    : mesh_(mesh), values_(std::move(values)), tree_(mesh) {
  for (const auto& field : values_)
    TEXSIM_VERIFY(field.size() == mesh_.positions.size(),
                  "field with " << field.size() << " values on " << mesh_.positions.size()
                                << " vertices");
}

SurfaceFieldSampler::Location SurfaceFieldSampler::locate(const Vec3& point) const {
  const auto closest = tree_.closest_point(point);
  const auto& t = mesh_.triangles[std::size_t(closest.triangle)];
  return {t,
          barycentric_weights(mesh_.positions[std::size_t(t[0])],
                              mesh_.positions[std::size_t(t[1])],
                              mesh_.positions[std::size_t(t[2])], closest.point),
          closest.distance};
}

double SurfaceFieldSampler::interpolate(const Location& at, std::size_t k) const {
  const auto& field = values_[k];
  const auto& t = at.corners;
  return at.weights[0] * field[std::size_t(t[0])] + at.weights[1] * field[std::size_t(t[1])] +
         at.weights[2] * field[std::size_t(t[2])];
}

SurfaceFieldSampler::Sampled SurfaceFieldSampler::sample_all(std::span<const Vec3> points) const {
  Sampled sampled;
  sampled.values.assign(values_.size(), std::vector<double>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Location at = locate(points[i]);
    sampled.max_distance = std::max(sampled.max_distance, at.distance);
    for (std::size_t k = 0; k < values_.size(); ++k)
      sampled.values[k][i] = interpolate(at, k);
  }
  return sampled;
}

std::vector<double> SurfaceFieldSampler::sample(std::size_t k, std::span<const Vec3> points) const {
  TEXSIM_VERIFY(k < values_.size(), "field " << k << " of " << values_.size());
  std::vector<double> result(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    result[i] = interpolate(locate(points[i]), k);
  return result;
}

} // namespace texsim::geom
