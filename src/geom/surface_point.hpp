#pragma once
/// A location on a triangle surface: a position together with the triangle that holds it.
#include "geom/triangle_mesh.hpp"

#include <cstdint>

namespace texsim::geom {

/// `position` (model units) lies on triangle `triangle` (an index into mesh.triangles); -1 when
/// the point is not placed yet.
struct SurfacePoint {
  Vec3 position = Vec3::Zero();
  std::int32_t triangle = -1;
};

} // namespace texsim::geom
