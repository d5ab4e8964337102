#pragma once
/// The sharp edges of a surface, for subdivision's crease rules (Hoppe et al. 1994): an edge
/// whose two triangles' normals differ by more than an angle. Serial, not collective; on a rank's
/// part of a distributed mesh every rank gets the same flags for the edges it shares, since they
/// depend on the positions alone.
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <vector>

namespace texsim::geom {

/// Per edge of `topology` (1 for a crease): edges of two triangles whose unit normals make an
/// angle above `angle_deg` degrees (180: none). Boundary edges are not flagged (they are sharp
/// anyway).
std::vector<char> crease_edges(const TriangleMesh& mesh, const MeshTopology& topology,
                               double angle_deg);

} // namespace texsim::geom
