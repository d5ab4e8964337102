#include "geom/random_surface_points.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace texsim::geom {

AreaPrefixSums area_prefix_sums(const TriangleMesh& mesh) {
  const auto areas = triangle_areas(mesh);
  AreaPrefixSums prefix;
  prefix.sums.resize(areas.size());
  double sum = 0.0;
  for (std::size_t t = 0; t < areas.size(); ++t) {
    sum += areas[t];
    prefix.sums[t] = sum;
    if (areas[t] > 0.0)
      prefix.last_positive = static_cast<std::int32_t>(t);
  }
  return prefix;
}

AreaSampler::AreaSampler(const TriangleMesh& mesh) : mesh_(mesh) {
  auto prefix = area_prefix_sums(mesh_);
  prefix_areas_ = std::move(prefix.sums);
  last_positive_ = prefix.last_positive;
  const double sum = prefix_areas_.empty() ? 0.0 : prefix_areas_.back();
  TEXSIM_VERIFY(last_positive_ >= 0 && sum > 0.0,
                "AreaSampler: the mesh has no triangle of positive area (" << mesh_.num_triangles()
                                                                           << " triangles)");
}

std::int32_t AreaSampler::triangle_for(double u) const {
  const double target = u * prefix_areas_.back();
  const auto it = std::upper_bound(prefix_areas_.begin(), prefix_areas_.end(), target);
  // u * total may round up to total itself; the last triangle of positive area takes that case.
  const auto t = static_cast<std::int32_t>(it - prefix_areas_.begin());
  return std::min(t, last_positive_);
}

SurfacePoint AreaSampler::sample(const CounterRng& rng, std::uint64_t id) const {
  const std::int32_t t = triangle_for(rng.uniform(id, 0, 0));
  // Square-root warping makes the barycentric coordinates uniform over the triangle's area.
  const double s = std::sqrt(rng.uniform(id, 0, 1));
  const double v = rng.uniform(id, 0, 2);
  const auto& tri = mesh_.triangles[t];
  SurfacePoint point;
  point.position = (1.0 - s) * mesh_.positions[tri[0]] + (s * (1.0 - v)) * mesh_.positions[tri[1]] +
                   (s * v) * mesh_.positions[tri[2]];
  point.triangle = t;
  return point;
}

std::vector<SurfacePoint> random_surface_points(const TriangleMesh& mesh, std::int64_t first_id,
                                                std::int64_t count, std::uint64_t seed) {
  TEXSIM_VERIFY(first_id >= 0 && count >= 0, "random_surface_points: first_id "
                                                 << first_id << " and count " << count
                                                 << " must not be negative");
  const AreaSampler sampler(mesh);
  const CounterRng rng(seed, kRandomSurfacePointStream);
  std::vector<SurfacePoint> points(static_cast<std::size_t>(count));
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i)
    points[i] = sampler.sample(rng, static_cast<std::uint64_t>(first_id + i));
  return points;
}

} // namespace texsim::geom
