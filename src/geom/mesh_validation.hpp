#pragma once
/// Finding and repairing defects of triangle meshes read from user files.
#include "geom/triangle_mesh.hpp"

#include <cstddef>
#include <string>

namespace texsim::geom {

/// How many elements have one kind of defect, and which came first.
struct MeshIssue {
  std::size_t count = 0;
  std::string first; ///< The first offending element in words, e.g. "vertices 12-40 shared by 3
                     ///< triangles"; empty when count == 0.

  explicit operator bool() const { return count > 0; }
};

/// Everything validate() checks. Topological checks (from duplicate_triangles on) are skipped, with
/// count 0, when some index is out of range.
struct MeshReport {
  MeshIssue non_finite_vertices;   ///< a NaN or infinite coordinate
  MeshIssue out_of_range_indices;  ///< triangles with an index outside [0, num_vertices)
  MeshIssue degenerate_triangles;  ///< a repeated index, or area <= tolerance * mean edge length^2
  MeshIssue duplicate_triangles;   ///< same vertex set as an earlier triangle (any orientation)
  MeshIssue unreferenced_vertices; ///< used by no triangle
  MeshIssue non_manifold_edges;    ///< shared by more than two triangles
  MeshIssue non_manifold_vertices; ///< incident triangles form more than one fan
  MeshIssue inconsistent_orientation; ///< interior edges traversed in the same direction by both
                                      ///< triangles
  std::size_t boundary_edges = 0;

  /// True when no defect at all was found (boundaries are not defects).
  bool clean() const;
};

/// What repair() and read_mesh() do. The defaults make any file texsim can use into a clean mesh.
struct MeshRepairOptions {
  /// Give exactly equal positions one vertex (STL and per-face OBJ exports store vertices per
  /// triangle).
  bool merge_coincident_vertices = true;
  /// Drop triangles with a repeated index or an area <= degenerate_area_tolerance * (mean edge
  /// length)^2.
  bool drop_degenerate_triangles = true;
  double degenerate_area_tolerance = 1e-12;
  /// Drop triangles whose vertex set equals an earlier triangle's, keeping the first.
  bool drop_duplicate_triangles = true;
  /// Drop vertices no triangle uses and renumber the rest, keeping their order.
  bool drop_unreferenced_vertices = true;
  /// Refuse meshes with an edge shared by more than two triangles.
  bool require_manifold_edges = true;
};

/// What repair() changed, for pipelines to log.
struct RepairReport {
  std::size_t merged_vertices = 0;
  std::size_t dropped_degenerate_triangles = 0;
  std::size_t dropped_duplicate_triangles = 0;
  std::size_t dropped_unreferenced_vertices = 0;

  bool changed() const;
  /// One line for the log, e.g. "merged coincident vertices: 4, dropped degenerate triangles: 2",
  /// or "no repairs".
  std::string summary() const;
};

/// Checks a mesh for every defect listed in MeshReport. Never throws on a bad mesh. Serial.
MeshReport validate(const TriangleMesh& mesh, double degenerate_area_tolerance = 1e-12);

/// Repairs `mesh` in place, in this order: merge coincident vertices, drop degenerate triangles,
/// drop duplicate triangles, drop unreferenced vertices (each as enabled in `options`). Throws
/// texsim::InputError naming `source_name` for what cannot be repaired: non-finite coordinates,
/// out-of-range indices, no triangles left, and (with require_manifold_edges) non-manifold edges,
/// e.g. "bunny.off: 3 non-manifold edges (first: vertices 12-40 shared by 3 triangles); texsim
/// needs a manifold surface". Serial.
RepairReport repair(TriangleMesh& mesh, const MeshRepairOptions& options,
                    const std::string& source_name);

} // namespace texsim::geom
