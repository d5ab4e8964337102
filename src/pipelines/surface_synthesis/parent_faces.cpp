#include "pipelines/surface_synthesis/parent_faces.hpp"

namespace texsim::pipelines::surface_synthesis {

std::array<double, 3> barycentric_weights(const geom::TriangleMesh& mesh, std::int32_t t,
                                          const geom::Vec3& point) {
  const auto& tri = mesh.triangles[std::size_t(t)];
  const geom::Vec3& a = mesh.positions[std::size_t(tri[0])];
  const geom::Vec3 ab = mesh.positions[std::size_t(tri[1])] - a;
  const geom::Vec3 ac = mesh.positions[std::size_t(tri[2])] - a;
  const geom::Vec3 ap = point - a;
  // Least squares in the triangle's plane (Gram matrix): exact for points on the plane.
  const double d00 = ab.dot(ab), d01 = ab.dot(ac), d11 = ac.dot(ac);
  const double d20 = ap.dot(ab), d21 = ap.dot(ac);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0))
    return {1.0, 0.0, 0.0};
  const double v = (d11 * d20 - d01 * d21) / det;
  const double w = (d00 * d21 - d01 * d20) / det;
  return {1.0 - v - w, v, w};
}

std::vector<ParentFace> find_parent_faces(std::span<const geom::Vec3> points,
                                          std::span<const geom::Vec3> normals,
                                          const geom::TriangleMesh& coarse,
                                          const geom::AabbTree& coarse_tree) {
  std::vector<ParentFace> parents(points.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < std::int64_t(points.size()); ++i) {
    const auto hit = coarse_tree.nearest_line_hit(points[std::size_t(i)], normals[std::size_t(i)]);
    if (!hit)
      continue;
    auto& parent = parents[std::size_t(i)];
    parent.triangle = hit->triangle;
    parent.vertices = coarse.triangles[std::size_t(hit->triangle)];
    parent.weights = barycentric_weights(coarse, hit->triangle, hit->point);
  }
  return parents;
}

} // namespace texsim::pipelines::surface_synthesis
