#include "geom/crease_edges.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace texsim::geom {

std::vector<char> crease_edges(const TriangleMesh& mesh, const MeshTopology& topology,
                               double angle_deg) {
  std::vector<char> crease(std::size_t(topology.num_edges()), 0);
  if (angle_deg >= 180.0)
    return crease;
  const double cos_limit = std::cos(angle_deg * std::numbers::pi / 180.0);
  const auto normal = [&](std::int32_t t) {
    const auto& tri = mesh.triangles[std::size_t(t)];
    const Vec3& a = mesh.positions[std::size_t(tri[0])];
    return Vec3((mesh.positions[std::size_t(tri[1])] - a)
                    .cross(mesh.positions[std::size_t(tri[2])] - a)
                    .normalized());
  };
  for (std::int32_t e = 0; e < topology.num_edges(); ++e) {
    const auto around = topology.edge_triangles(e);
    if (around.size() == 2)
      crease[std::size_t(e)] = normal(around[0]).dot(normal(around[1])) < cos_limit ? 1 : 0;
  }
  return crease;
}

} // namespace texsim::geom
