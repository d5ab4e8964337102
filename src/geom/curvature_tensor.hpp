#pragma once
/// Per-vertex curvature tensors of a triangle surface: normal, principal curvatures and principal
/// directions, estimated from the change of the vertex normals over each triangle (Rusinkiewicz,
/// "Estimating Curvatures and Their Derivatives on Triangle Meshes", 3DPVT 2004).
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <vector>

namespace texsim::geom {

/// Curvature frame of one vertex. `normal`, `e1`, `e2` are unit vectors forming a right-handed
/// orthonormal frame (e1 x e2 = normal). k1 >= k2 are the principal curvatures in 1/model units,
/// signed as the derivative of the outward normal: +1/r on a sphere of radius r whose triangles
/// face outwards, negative in saddle or concave directions. e1 is the direction of k1, e2 of k2.
struct PrincipalCurvature {
  Vec3 normal;
  Vec3 e1;
  Vec3 e2;
  double k1 = 0.0;
  double k2 = 0.0;
};

/// Principal curvatures and directions of every vertex, indexed like mesh.positions.
///
/// Vertex normals are the sum of the incident triangles' corner cross products weighted by the
/// inverse squared lengths of the two corner edges (Max 1999; exact for vertices on a sphere). Each
/// triangle fits the second fundamental form that best maps its three edge vectors to the
/// differences of the vertex normals along them (least squares, in the triangle's plane); the
/// fitted tensor is rotated into each corner's tangent frame and averaged over the incident
/// triangles with the corner's mixed Voronoi area as weight (Meyer et al. 2003).
///
/// Boundary vertices: a one-sided Max normal leans inwards by about half an edge's turn, which
/// would halve the curvature across the boundary, so a boundary vertex's normal is instead taken
/// from a least-squares quadratic height field through it over its two-ring (kept one-sided when
/// the two-ring is too small or degenerate); its tensor then averages the triangles it has.
/// Zero-area triangles are skipped. A vertex without usable triangles gets
/// k1 = k2 = 0, a unit normal from whatever triangles it has (or +z) and an arbitrary tangent
/// frame. `topology` must be built from `mesh`. Serial result, OpenMP-parallel over triangles and
/// vertices; deterministic (independent of the thread count). Not collective.
std::vector<PrincipalCurvature> principal_curvatures(const TriangleMesh& mesh,
                                                     const MeshTopology& topology);

} // namespace texsim::geom
