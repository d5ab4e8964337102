#pragma once
/// The fluid's velocity, wherever the patches' vertices are, at any time of one frame step.
#include "geom/triangle_mesh.hpp"

namespace texsim::pipelines::fluid_lapped {

/// Velocity of the fluid (model units per unit of time). Implementations are immutable after
/// construction, so at() may be called from many threads at once.
class VelocityField {
public:
  virtual ~VelocityField() = default;
  /// Velocity at `position` and time `time`.
  virtual geom::Vec3 at(const geom::Vec3& position, double time) const = 0;
};

} // namespace texsim::pipelines::fluid_lapped
