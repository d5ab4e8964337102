#pragma once
/// How rough a surface is: the mean angle between the normals of triangles sharing an edge. Noise
/// raises it; smoothing lowers it; sharp features contribute their dihedral angles.
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

namespace texsim::geom {

/// Mean over interior edges of the angle (degrees) between the two triangles' normals. Serial.
double mean_normal_deviation_deg(const TriangleMesh& mesh, const MeshTopology& topology);

} // namespace texsim::geom
