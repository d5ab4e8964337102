#pragma once
/// Creating a patch (section 4, Fig. 3): the triangles of the fluid surface near a centre p that
/// face p's side, copied into a small mesh and flattened by LSCM into the patch's rest uv.
#include "geom/surface_point.hpp"
#include "pipelines/fluid_lapped/frame_surface.hpp"
#include "pipelines/fluid_lapped/patch.hpp"

#include <cstdint>

namespace texsim::pipelines::fluid_lapped {

/// CounterRng stream of the patches' rotations.
inline constexpr std::uint32_t kPatchRotationStream = 0x5403;

/// The patch of `id` centred at `centre` on `frame`: the triangles whose closest point is within
/// `radius` of p and whose normal faces p's side (n_t . n_p > 0, n_p the normal of p's
/// triangle), grown over edges from p's triangle nearest first (ties: lower id), a triangle
/// joining only while the patch stays one topological disk (glued along one edge with a new
/// third vertex, or along two edges)†. Flattened by geom::lscm_parameterize, scaled so its uv
/// area equals its surface area, turned by an angle uniform in [0, 2 pi) from
/// CounterRng(seed, kPatchRotationStream) keyed by `rotation_key`†, moved so p sits at (0.5, 0.5)
/// and scaled by 0.5 / radius (distance r -> 0.5)†. If LSCM fails, the growth is retried with a
/// radius shrunk by 3/4 until it succeeds (p's triangle alone is laid out isometrically).
/// Vertices and their surface_triangle are where project_patch() would put them (closest
/// point), so a still fluid leaves a patch as it was built; weights are left at 0 for
/// update_weights(). Serial; deterministic.
Patch build_patch(const FrameSurface& frame, const geom::SurfacePoint& centre, double radius,
                  std::int64_t id, std::int32_t frame_index, std::uint64_t seed,
                  std::uint64_t rotation_key);

/// The rotation key of a patch created at frame `frame_index` for atlas texel (x, y): where it
/// was made, not its id, so how the candidates were batched cannot change the texture. Frame 0's
/// Poisson-disk patches are keyed by their index, below every created patch's key.
std::uint64_t created_patch_rotation_key(std::int32_t frame_index, int x, int y);

} // namespace texsim::pipelines::fluid_lapped
