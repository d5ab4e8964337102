#pragma once
/// Sums over a distributed surface: each rank adds its owned triangles (or the edges whose smaller
/// global vertex it owns) and one allreduce combines them. Rounding may differ between rank
/// counts; it does not differ between runs at one rank count.
#include "geom/distributed_mesh.hpp"

namespace texsim::geom {

/// Total area of the surface. Collective.
double total_area(const DistributedMesh& mesh);

/// Mean edge length over every triangle's three edges (as geom::mean_edge_length): the same bits
/// at any rank count (par::reproducible_sum). Collective.
double mean_edge_length(const DistributedMesh& mesh);

/// Edges of the surface with a single triangle (0 for a closed surface). Collective.
std::int64_t boundary_edge_count(const DistributedMesh& mesh);

/// Crease edges of the surface (DistributedMesh::creases; 0 without). Collective.
std::int64_t crease_edge_count(const DistributedMesh& mesh);

/// As geom::mean_normal_deviation_deg on the whole surface. Collective.
double mean_normal_deviation_deg(const DistributedMesh& mesh);

} // namespace texsim::geom
