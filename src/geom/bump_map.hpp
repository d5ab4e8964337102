#pragma once
/// Bump mapping a surface with a scalar height field (e.g. a rendered reaction-diffusion pattern,
/// Turk 1991): the displaced copy of the mesh and the normals a renderer shades the undisplaced
/// mesh with to show the bumps. Serial; model units.
#include "geom/triangle_mesh.hpp"

#include <span>
#include <vector>

namespace texsim::geom {

/// A bump-mapped copy of a mesh, indexed like its vertices (the triangles are the mesh's).
struct BumpedSurface {
  std::vector<Vec3> positions; ///< each vertex moved along its unit normal by scale * height[v]
  std::vector<Vec3> normals;   ///< unit area-weighted vertex normals of the displaced surface
};

/// Moves every vertex v along the area-weighted unit vertex normal of `mesh` by scale * height[v]
/// (model units: height times scale) and returns the displaced positions with their perturbed
/// normals, i.e. the area-weighted vertex normals of the displaced surface (zero where those
/// vanish, as in vertex_normals()). Needs height.size() == mesh.num_vertices() and a finite scale;
/// throws Error otherwise.
BumpedSurface bump_map(const TriangleMesh& mesh, std::span<const double> height, double scale);

} // namespace texsim::geom
