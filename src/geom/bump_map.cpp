#include "geom/bump_map.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"

#include <cmath>
#include <utility>

namespace texsim::geom {

BumpedSurface bump_map(const TriangleMesh& mesh, std::span<const double> height, double scale) {
  TEXSIM_VERIFY(height.size() == mesh.positions.size(),
                "bump_map: " << height.size() << " heights for " << mesh.num_vertices()
                             << " vertices");
  TEXSIM_VERIFY(std::isfinite(scale), "bump_map: scale must be finite, got " << scale);
  const std::vector<Vec3> normals = vertex_normals(mesh);

  TriangleMesh displaced;
  displaced.triangles = mesh.triangles;
  displaced.positions.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    displaced.positions[v] = mesh.positions[v] + (scale * height[v]) * normals[v];

  BumpedSurface bumped;
  bumped.normals = vertex_normals(displaced);
  bumped.positions = std::move(displaced.positions);
  return bumped;
}

} // namespace texsim::geom
