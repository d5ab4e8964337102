#pragma once
/// Loop subdivision of triangle surfaces.
#include "geom/triangle_mesh.hpp"

namespace texsim::geom {

/// Applies `levels` rounds of Loop subdivision (Loop 1987, the masks of CGAL's Loop_mask_3): each
/// round splits every triangle into four and smooths the positions with Loop's masks, so a closed
/// mesh with V vertices and E edges gets V + E vertices and 4x the triangles per round. Vertices
/// are numbered by patch_refinement's hierarchical ids (the input's vertices keep theirs), which is
/// what lets DistributedMesh refine the same surface on the ranks' parts. The input must be
/// edge-manifold and consistently oriented (repair() output of a manifold file); throws
/// texsim::Error on non-manifold edges. levels >= 0. Serial.
TriangleMesh loop_subdivide(const TriangleMesh& mesh, int levels);

} // namespace texsim::geom
