#pragma once
/// Edge-collapse simplification of triangle surfaces (CGAL).
#include "geom/triangle_mesh.hpp"

#include <cstddef>

namespace texsim::geom {

/// Collapses edges in order of Lindstrom-Turk cost, placing each merged vertex by Lindstrom-Turk's
/// volume- and boundary-preserving placement (CGAL's Surface_mesh_simplification), until the mesh
/// has at most `target_triangles` triangles or no edge can be collapsed without breaking the
/// topology. Topology (closedness, genus, boundary loops) is kept; vertices and triangles are
/// renumbered. A mesh already at or below the target is returned unchanged. The input must be an
/// edge-manifold, consistently oriented mesh; throws texsim::Error otherwise. Serial.
TriangleMesh simplify(const TriangleMesh& mesh, std::size_t target_triangles);

} // namespace texsim::geom
