#include "geom/surface_roughness.hpp"

#include "geom/mesh_measures.hpp"

#include <algorithm>
#include <cmath>

namespace texsim::geom {

double mean_normal_deviation_deg(const TriangleMesh& mesh, const MeshTopology& topology) {
  const auto normals = triangle_normals(mesh);
  double sum = 0;
  std::int64_t edges = 0;
  for (std::int32_t e = 0; e < topology.num_edges(); ++e) {
    const auto triangles = topology.edge_triangles(e);
    if (triangles.size() != 2)
      continue;
    const double cosine = std::clamp(normals[triangles[0]].dot(normals[triangles[1]]), -1.0, 1.0);
    sum += std::acos(cosine);
    ++edges;
  }
  return edges ? sum / double(edges) * 180.0 / M_PI : 0.0;
}

} // namespace texsim::geom
