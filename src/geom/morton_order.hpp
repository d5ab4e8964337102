#pragma once
/// Surface points spread over ranks, put in order along a Morton (Z-order) curve inside a box
/// every rank knows (the mesh's bounding box), so that the same point gets the same key whichever
/// other points a rank holds.
#include "geom/point_halo.hpp"
#include "geom/surface_point.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <vector>

namespace texsim::geom {

/// The points of all ranks sorted by (Morton key in `box`, id), as par::distributed_sort leaves
/// them: rank r holds the even run of sorted positions floor(position p / n) = r, in curve order.
/// Ids must be unique over the ranks. Collective.
DistributedSurfacePoints sort_along_morton_curve(const par::Comm& comm, const Box3& box,
                                                 DistributedSurfacePoints points);

/// The triangles' indices in the order of their centroids' Morton keys inside the centroids'
/// bounding box (ties: index). Serial.
std::vector<std::size_t> morton_triangle_order(const TriangleMesh& mesh);

/// The part in [0, parts) of each triangle: even runs along a Morton curve of the triangles'
/// centroids (par::morton_partition). The same on every rank that holds the mesh. Serial.
std::vector<int> morton_triangle_parts(const TriangleMesh& mesh, int parts);

} // namespace texsim::geom
