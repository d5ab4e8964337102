#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_topology.hpp"

#include <cmath>

namespace texsim::geom {
namespace {

TriangleMesh icosahedron() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh mesh;
  mesh.positions = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                    {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                    {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  return mesh;
}

/// Splits every triangle into four; the midpoint of edge e becomes vertex V + e.
TriangleMesh split_at_midpoints(const TriangleMesh& mesh) {
  const MeshTopology topo(mesh);
  TriangleMesh fine;
  fine.positions = mesh.positions;
  fine.positions.reserve(mesh.positions.size() + topo.edges().size());
  for (const auto& [a, b] : topo.edges()) {
    fine.positions.push_back(0.5 * (mesh.positions[a] + mesh.positions[b]));
  }
  fine.triangles.reserve(4 * mesh.triangles.size());
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& tri = mesh.triangles[t];
    std::array<std::int32_t, 3> mid; // mid[i] sits on the side opposite corner i
    for (int i = 0; i < 3; ++i) {
      mid[i] = mesh.num_vertices() + topo.triangle_edges(t)[i];
    }
    fine.triangles.push_back({tri[0], mid[2], mid[1]});
    fine.triangles.push_back({tri[1], mid[0], mid[2]});
    fine.triangles.push_back({tri[2], mid[1], mid[0]});
    fine.triangles.push_back({mid[0], mid[1], mid[2]});
  }
  return fine;
}

} // namespace

TriangleMesh icosphere(int level, double radius) {
  TEXSIM_VERIFY(level >= 0 && level <= 10, "icosphere: level " << level << " outside [0, 10]");
  TEXSIM_VERIFY(radius > 0.0, "icosphere: radius " << radius << " must be positive");
  auto mesh = icosahedron();
  for (int l = 0; l < level; ++l) {
    mesh = split_at_midpoints(mesh);
    for (auto& p : mesh.positions) {
      p.normalize();
    }
  }
  for (auto& p : mesh.positions) {
    p = radius * p.normalized();
  }
  return mesh;
}

} // namespace texsim::geom
