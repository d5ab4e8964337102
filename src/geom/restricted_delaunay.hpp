#pragma once
/// The restricted Delaunay triangulation of seed points on a surface: the dual of their
/// restricted Voronoi diagram (restricted_voronoi.hpp), one triangle for every point of the
/// surface where three cells meet. It is how Turk's retiling (1992) and Wei-Levoy's mesh levels
/// turn evenly spread points into a mesh whose vertices are those points.
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <span>

namespace texsim::geom {

/// Vertex i of the result is seeds[i]; a triangle (i, a, b) for every vertex of the restricted
/// Voronoi diagram where the cells of seeds i, a and b meet inside a triangle of `surface`,
/// counter-clockwise seen from the side the surface triangle faces. Each triple appears once
/// (a vertex exactly on a surface edge is found from both sides), rotated to start at its smallest
/// seed id; triangles are sorted, so the result depends on neither thread count nor triangle
/// order. Where more than three cells meet at one point, or a triple meets twice, the result is
/// not a manifold: callers check it with MeshTopology. Not collective; OpenMP inside.
TriangleMesh restricted_delaunay(const TriangleMesh& surface, std::span<const Vec3> seeds,
                                 std::span<const std::int64_t> seed_ids);

} // namespace texsim::geom
