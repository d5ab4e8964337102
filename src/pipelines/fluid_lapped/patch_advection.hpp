#pragma once
/// Carrying patches with the flow (section 4): every vertex advected on its own, then projected
/// onto the next frame's surface; vertices that end up far from it (splashes, droplets,
/// topology changes) are removed with their triangles.
#include "pipelines/fluid_lapped/frame_surface.hpp"
#include "pipelines/fluid_lapped/patch.hpp"
#include "pipelines/fluid_lapped/velocity_field.hpp"

namespace texsim::pipelines::fluid_lapped {

struct AdvectionSettings {
  /// Longest distance a vertex may move in one substep: half an edge of the frame†.
  double max_step_length = 0;
  /// Substeps are multiplied by this (convergence studies; 1 in production).
  int substep_multiplier = 1;
};

/// Moves every vertex from time t0 to t1 with classical RK4, n = multiplier x max(1,
/// ceil(|v(x, t0)| (t1 - t0) / max_step_length)) equal substeps chosen per vertex, so the result
/// does not depend on which rank holds the patch. OpenMP over vertices; deterministic.
void advect_patch(Patch& patch, const VelocityField& velocity, double t0, double t1,
                  const AdvectionSettings& settings);

/// Projects every vertex onto `next` (closest point; surface_triangle updated), removes the
/// vertices farther than radius / 4 from it and the triangles using them, then the vertices no
/// triangle uses (order kept; rest_uv and weights follow). Weights are not recomputed.
void project_patch(Patch& patch, const FrameSurface& next, double radius);

} // namespace texsim::pipelines::fluid_lapped
