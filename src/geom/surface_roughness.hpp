#pragma once
/// How rough a surface is: the mean angle between the normals of triangles sharing an edge. Noise
/// raises it; smoothing lowers it; sharp features contribute their dihedral angles.
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <functional>

namespace texsim::geom {

/// Sum over interior edges of the angle (radians) between the two triangles' normals, and how
/// many edges it counts.
struct NormalDeviationSum {
  double radians = 0;
  std::int64_t edges = 0;
};

/// The sum over the interior edges that `counted(edge id)` selects. Serial.
NormalDeviationSum normal_deviation_sum(const TriangleMesh& mesh, const MeshTopology& topology,
                                        const std::function<bool(std::int32_t)>& counted);

/// Mean over interior edges of the angle (degrees) between the two triangles' normals. Serial.
double mean_normal_deviation_deg(const TriangleMesh& mesh, const MeshTopology& topology);

/// The mean of a sum, in degrees (0 without edges).
double mean_degrees(const NormalDeviationSum& sum);

} // namespace texsim::geom
