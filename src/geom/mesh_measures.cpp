#include "geom/mesh_measures.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <numeric>

namespace texsim::geom {
namespace {

Vec3 doubled_area_vector(const TriangleMesh& mesh, const Triangle& tri) {
  const auto& a = mesh.positions[tri[0]];
  return (mesh.positions[tri[1]] - a).cross(mesh.positions[tri[2]] - a);
}

Vec3 normalized_or_zero(const Vec3& v) {
  const double norm = v.norm();
  return norm > 0.0 ? Vec3(v / norm) : Vec3::Zero();
}

} // namespace

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

std::array<double, 3> barycentric_weights(const Vec3& a, const Vec3& b, const Vec3& c,
                                          const Vec3& p) {
  const Vec3 e1 = b - a;
  const Vec3 e2 = c - a;
  const Vec3 d = p - a;
  // The 2x2 normal equations of d = u e1 + v e2.
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
  const double det = g11 * g22 - g12 * g12;
  const double d1 = d.dot(e1), d2 = d.dot(e2);
  const double u = det > 0 ? (g22 * d1 - g12 * d2) / det : 0.0;
  const double v = det > 0 ? (g11 * d2 - g12 * d1) / det : 0.0;
  return {1 - u - v, u, v};
}

std::vector<double> triangle_areas(const TriangleMesh& mesh) {
  std::vector<double> areas(mesh.triangles.size());
  for (std::size_t t = 0; t < areas.size(); ++t) {
    areas[t] = 0.5 * doubled_area_vector(mesh, mesh.triangles[t]).norm();
  }
  return areas;
}

double total_area(const TriangleMesh& mesh) {
  const auto areas = triangle_areas(mesh);
  return std::accumulate(areas.begin(), areas.end(), 0.0);
}

std::vector<Vec3> triangle_normals(const TriangleMesh& mesh) {
  std::vector<Vec3> normals(mesh.triangles.size());
  for (std::size_t t = 0; t < normals.size(); ++t) {
    normals[t] = normalized_or_zero(doubled_area_vector(mesh, mesh.triangles[t]));
  }
  return normals;
}

std::vector<Vec3> vertex_normals(const TriangleMesh& mesh) {
  return vertex_normals(mesh, 0, mesh.num_vertices());
}

std::vector<Vec3> vertex_normals(const TriangleMesh& mesh, std::int64_t first, std::int64_t count) {
  std::vector<Vec3> normals(static_cast<std::size_t>(count), Vec3::Zero());
  for (const auto& tri : mesh.triangles) {
    if (std::none_of(tri.begin(), tri.end(),
                     [&](std::int32_t v) { return v >= first && v < first + count; }))
      continue;
    // The cross product's length is twice the area: summing it weights normals by area.
    const Vec3 weighted = doubled_area_vector(mesh, tri);
    for (const auto v : tri) {
      if (v >= first && v < first + count)
        normals[static_cast<std::size_t>(v - first)] += weighted;
    }
  }
  for (auto& n : normals) {
    n = normalized_or_zero(n);
  }
  return normals;
}

double mean_edge_length(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) {
    return 0.0;
  }
  double sum = 0.0;
  for (const auto& tri : mesh.triangles) {
    for (int i = 0; i < 3; ++i) {
      sum += (mesh.positions[tri[(i + 1) % 3]] - mesh.positions[tri[i]]).norm();
    }
  }
  return sum / (3.0 * static_cast<double>(mesh.triangles.size()));
}

} // namespace texsim::geom
