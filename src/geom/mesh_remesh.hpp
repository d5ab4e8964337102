#pragma once
/// Isotropic remeshing (CGAL Polygon Mesh Processing): replaces the slivers and needles of raw
/// scans and marching-cubes meshes by nearly equilateral triangles of a chosen edge length, the
/// usual first step before FEM on such surfaces (a sliver makes the P1 system badly conditioned).
#include "geom/triangle_mesh.hpp"

namespace texsim::geom {

struct RemeshOptions {
  double edge_length = 0.0; ///< target edge length, in the mesh's units (after `scale`)
  int iterations = 3;       ///< split/collapse/flip/relax rounds
};

/// Remeshes a manifold, consistently oriented mesh towards edges of `options.edge_length`, with
/// CGAL's isotropic_remeshing. Boundary loops are protected: their edges longer than 4/3 of the
/// target are split first (points added on the boundary), none is collapsed or moved, so the
/// boundary keeps its shape. Vertices are projected back onto the input surface. Serial;
/// deterministic.
TriangleMesh remesh_isotropic(const TriangleMesh& mesh, const RemeshOptions& options);

} // namespace texsim::geom
