#pragma once
/// Uniformly distributed random points on a triangle surface (area-weighted), keyed by a global
/// point id so that the same id gives the same point on every rank and for any split of the ids.
#include "core/rng.hpp"
#include "geom/surface_point.hpp"
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <vector>

namespace texsim::geom {

/// CounterRng stream used by random_surface_points().
inline constexpr std::uint32_t kRandomSurfacePointStream = 0x5401;

/// Inclusive prefix sums of the triangle areas in id order (the last one is total_area's bits),
/// and the last triangle of positive area (-1 when there is none). Serial.
struct AreaPrefixSums {
  std::vector<double> sums;
  std::int32_t last_positive = -1;
};
AreaPrefixSums area_prefix_sums(const TriangleMesh& mesh);

/// Draws points uniformly with respect to surface area. Keeps a copy of the mesh (the argument
/// may be destroyed afterwards). sample() is const and thread-safe. Serial, not collective.
class AreaSampler {
public:
  /// Throws texsim::Error when the mesh has no triangle of positive area.
  explicit AreaSampler(const TriangleMesh& mesh);

  /// Point `id`: its triangle is chosen with probability proportional to area from
  /// rng.uniform(id, 0, 0) (binary search in the prefix sums of the areas, so zero-area triangles
  /// are never chosen), its barycentric coordinates uniformly from draws 1 and 2
  /// (1 - sqrt(u1), sqrt(u1) (1 - u2), sqrt(u1) u2).
  SurfacePoint sample(const CounterRng& rng, std::uint64_t id) const;

  /// Sum of the triangle areas, model units squared.
  double total_area() const { return prefix_areas_.back(); }

  /// Triangle chosen for the uniform number u in [0, 1): the first triangle whose inclusive
  /// area prefix sum exceeds u * total_area().
  std::int32_t triangle_for(double u) const;

private:
  TriangleMesh mesh_;
  std::vector<double> prefix_areas_; ///< inclusive prefix sums of the triangle areas
  std::int32_t last_positive_ = -1;  ///< the last triangle of positive area
};

/// Points with ids first_id .. first_id + count - 1, each from
/// AreaSampler::sample(CounterRng(seed, kRandomSurfacePointStream), id). OpenMP over the points;
/// serial, not collective. Needs first_id >= 0 and count >= 0.
std::vector<SurfacePoint> random_surface_points(const TriangleMesh& mesh, std::int64_t first_id,
                                                std::int64_t count, std::uint64_t seed);

} // namespace texsim::geom
