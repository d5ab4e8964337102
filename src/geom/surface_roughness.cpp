#include "geom/surface_roughness.hpp"

#include "geom/mesh_measures.hpp"

#include <algorithm>
#include <cmath>

namespace texsim::geom {

NormalDeviationSum normal_deviation_sum(const TriangleMesh& mesh, const MeshTopology& topology,
                                        const std::function<bool(std::int32_t)>& counted) {
  const auto normals = triangle_normals(mesh);
  NormalDeviationSum sum;
  for (std::int32_t e = 0; e < topology.num_edges(); ++e) {
    const auto triangles = topology.edge_triangles(e);
    if (triangles.size() != 2 || !counted(e))
      continue;
    const double cosine = std::clamp(normals[triangles[0]].dot(normals[triangles[1]]), -1.0, 1.0);
    sum.radians += std::acos(cosine);
    ++sum.edges;
  }
  return sum;
}

double mean_degrees(const NormalDeviationSum& sum) {
  return sum.edges ? sum.radians / double(sum.edges) * 180.0 / M_PI : 0.0;
}

double mean_normal_deviation_deg(const TriangleMesh& mesh, const MeshTopology& topology) {
  return mean_degrees(normal_deviation_sum(mesh, topology, [](std::int32_t) { return true; }));
}

} // namespace texsim::geom
