#pragma once
/// Loop subdivision of triangle surfaces (CGAL).
#include "geom/triangle_mesh.hpp"

namespace texsim::geom {

/// Applies `levels` rounds of Loop subdivision (Loop 1987, through CGAL's Subdivision_method_3):
/// each round splits every triangle into four and smooths the positions with Loop's masks, so a
/// closed mesh with V vertices and E edges gets V + E vertices and 4x the triangles per round. The
/// input must be an edge-manifold, consistently oriented mesh (repair() output of a manifold file);
/// throws texsim::Error otherwise. levels >= 0. Serial.
TriangleMesh loop_subdivide(const TriangleMesh& mesh, int levels);

} // namespace texsim::geom
