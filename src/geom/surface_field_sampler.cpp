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

SurfaceFieldSampler::Sampled SurfaceFieldSampler::sample_all(std::span<const Vec3> points) const {
  Sampled sampled;
  sampled.values.assign(values_.size(), std::vector<double>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto closest = tree_.closest_point(points[i]);
    sampled.max_distance = std::max(sampled.max_distance, closest.distance);
    const auto& t = mesh_.triangles[std::size_t(closest.triangle)];
    const auto w =
        barycentric_weights(mesh_.positions[std::size_t(t[0])], mesh_.positions[std::size_t(t[1])],
                            mesh_.positions[std::size_t(t[2])], closest.point);
    for (std::size_t k = 0; k < values_.size(); ++k) {
      const auto& field = values_[k];
      sampled.values[k][i] = w[0] * field[std::size_t(t[0])] + w[1] * field[std::size_t(t[1])] +
                             w[2] * field[std::size_t(t[2])];
    }
  }
  return sampled;
}

std::vector<double> SurfaceFieldSampler::sample(std::size_t k, std::span<const Vec3> points) const {
  TEXSIM_VERIFY(k < values_.size(), "field " << k << " of " << values_.size());
  const auto& field = values_[k];
  std::vector<double> result(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto closest = tree_.closest_point(points[i]);
    const auto& t = mesh_.triangles[std::size_t(closest.triangle)];
    const auto w =
        barycentric_weights(mesh_.positions[std::size_t(t[0])], mesh_.positions[std::size_t(t[1])],
                            mesh_.positions[std::size_t(t[2])], closest.point);
    result[i] = w[0] * field[std::size_t(t[0])] + w[1] * field[std::size_t(t[1])] +
                w[2] * field[std::size_t(t[2])];
  }
  return result;
}

} // namespace texsim::geom
