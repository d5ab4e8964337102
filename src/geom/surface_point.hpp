#pragma once
/// A location on a triangle surface: a position together with the triangle that holds it.
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <vector>

namespace texsim::geom {

/// `position` (model units) lies on triangle `triangle` (an index into mesh.triangles); -1 when
/// the point is not placed yet.
struct SurfacePoint {
  Vec3 position = Vec3::Zero();
  std::int32_t triangle = -1;
};

/// Points owned by this rank: global ids and positions on the surface.
struct DistributedSurfacePoints {
  std::vector<std::int64_t> ids;
  std::vector<SurfacePoint> points;
};

} // namespace texsim::geom
