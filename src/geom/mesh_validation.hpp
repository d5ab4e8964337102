#pragma once
/// Finding and repairing defects of triangle meshes read from user files.
#include "geom/triangle_mesh.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

namespace texsim::geom {

class MeshTopology;

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

/// What repair() and read_mesh() do. The defaults make any file texsim could always use into a
/// clean mesh and refuse non-manifold edges; `mesh.repair: fix` (geom/mesh_source.hpp) also sets
/// split_non_manifold, min_component_fraction and fill_holes, `mesh.repair: strict` sets strict.
struct MeshRepairOptions {
  /// Give exactly equal positions one vertex (STL and per-face OBJ exports store vertices per
  /// triangle). Not a defect: strict mode merges them too.
  bool merge_coincident_vertices = true;
  /// Drop triangles with a repeated index or an area <= degenerate_area_tolerance * (mean edge
  /// length)^2.
  bool drop_degenerate_triangles = true;
  double degenerate_area_tolerance = 1e-12;
  /// Drop triangles whose vertex set equals an earlier triangle's, keeping the first.
  bool drop_duplicate_triangles = true;
  /// Drop vertices no triangle uses and renumber the rest, keeping their order.
  bool drop_unreferenced_vertices = true;
  /// Refuse meshes with an edge shared by more than two triangles (unless split_non_manifold).
  bool require_manifold_edges = true;
  /// Cut non-manifold edges and vertices apart and orient the triangles consistently
  /// (geom::split_non_manifold, CGAL) instead of refusing non-manifold edges.
  bool split_non_manifold = false;
  /// Drop connected components whose area is below this fraction of the largest component's area
  /// (0: keep all). Needs split_non_manifold or a manifold, oriented mesh.
  double min_component_fraction = 0.0;
  /// Close every boundary loop with a refined patch (geom::fill_holes, CGAL).
  bool fill_holes = false;
  /// Refuse, naming every defect found, instead of repairing: degenerate or duplicate triangles,
  /// non-manifold edges or vertices, inconsistent orientation, components below
  /// min_component_fraction. Coincident vertices are still merged and unused vertices dropped.
  bool strict = false;
};

/// What repair() found and changed, for pipelines to log and report.
struct RepairReport {
  std::size_t merged_vertices = 0;
  std::size_t dropped_degenerate_triangles = 0;
  std::size_t dropped_duplicate_triangles = 0;
  std::size_t dropped_unreferenced_vertices = 0;  ///< including those of dropped components
  std::size_t non_manifold_edges = 0;             ///< found before splitting
  std::size_t non_manifold_vertices = 0;          ///< found before splitting
  std::size_t inconsistent_orientation_edges = 0; ///< found before orienting
  std::size_t split_added_vertices = 0;           ///< vertex copies made by the split
  std::size_t reoriented_triangles = 0;
  std::size_t components = 0; ///< connected components before dropping (0: not counted)
  std::size_t dropped_components = 0;
  std::size_t dropped_component_triangles = 0;
  std::size_t filled_holes = 0;
  std::size_t hole_triangles = 0; ///< triangles added by the patches

  bool changed() const;
  /// One line for the log, e.g. "merged coincident vertices: 4, dropped degenerate triangles: 2",
  /// or "no repairs".
  std::string summary() const;
  /// Every count by name, for summary.json.
  nlohmann::json metrics() const;
};

/// Checks a mesh for every defect listed in MeshReport. Never throws on a bad mesh. Serial.
MeshReport validate(const TriangleMesh& mesh, double degenerate_area_tolerance = 1e-12);

/// MeshReport::inconsistent_orientation of `mesh` from its topology, for a caller that has built
/// it already (validate() builds its own). Serial.
MeshIssue inconsistent_orientation(const TriangleMesh& mesh, const MeshTopology& topology);

/// Repairs `mesh` in place, in this order: merge coincident vertices, drop degenerate triangles,
/// drop duplicate triangles, drop unreferenced vertices, split non-manifold edges and vertices and
/// orient, drop small components, fill holes (each as enabled in `options`). Throws
/// texsim::InputError naming `source_name` for what cannot be repaired: non-finite coordinates,
/// out-of-range indices, no triangles left, non-manifold edges (with require_manifold_edges and
/// without split_non_manifold), e.g. "bunny.off: 3 non-manifold edges (first: vertices 12-40
/// shared by 3 triangles); texsim needs a manifold surface", and with `strict` every defect
/// found. Serial; deterministic.
RepairReport repair(TriangleMesh& mesh, const MeshRepairOptions& options,
                    const std::string& source_name);

} // namespace texsim::geom
