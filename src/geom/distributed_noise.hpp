#pragma once
/// noisy() on a distributed surface: each rank moves its own vertices, then the halo follows.
#include "geom/distributed_mesh.hpp"

#include <cstdint>

namespace texsim::geom {

/// Moves every vertex along its area-weighted unit normal by amplitude x mean edge length x
/// U(-1, 1), the draw keyed by the vertex's input id as in noisy(): the same bits at any rank
/// count (the mean edge length is a reproducible sum, the normals sum their triangles in input
/// order). Collective.
void add_normal_noise(DistributedMesh& mesh, double amplitude, std::uint64_t seed);

} // namespace texsim::geom
