#pragma once
/// Poisson-disk points on a triangle surface: no two closer than a radius, and no room left for
/// another (maximal), the patch centres of lapped textures (Gagnon et al. 2019, 2021).
#include "geom/surface_point.hpp"
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <vector>

namespace texsim::geom {

/// CounterRng stream of the dart-throwing candidates.
inline constexpr std::uint32_t kPoissonDiskStream = 0x5402;

/// Points pairwise farther apart than `radius` (Euclidean): first dart throwing, greedy in id
/// order over 30 area / radius^2 AreaSampler candidates drawn from CounterRng(seed,
/// kPoissonDiskStream); then a deterministic fill over a dense set of surface samples (vertices,
/// and per triangle a barycentric grid with spacing at most radius / 8), each accepted in
/// triangle order when farther than `radius` from every point so far. Afterwards every sample of
/// that set lies within `radius` of a point, so every surface point lies within 1.125 radius of
/// one (maximal up to the fill's spacing). Serial; the same on every rank. Needs radius > 0.
std::vector<SurfacePoint> poisson_disk_points(const TriangleMesh& mesh, double radius,
                                              std::uint64_t seed);

} // namespace texsim::geom
