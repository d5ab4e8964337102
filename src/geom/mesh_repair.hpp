#pragma once
/// The topological repairs of raw scans and marching-cubes meshes, through CGAL Polygon Mesh
/// Processing: non-manifold edges and vertices split, triangles oriented consistently, tiny
/// connected components dropped, holes filled. geom::repair() calls these for `mesh.repair: fix`;
/// this header keeps CGAL out of its includers.
#include "geom/triangle_mesh.hpp"

#include <cstddef>

namespace texsim::geom {

/// What split_non_manifold() changed.
struct NonManifoldSplit {
  std::size_t added_vertices = 0;       ///< copies made to separate fans and sheets
  std::size_t reoriented_triangles = 0; ///< triangles whose corner order was reversed
};

/// Turns a mesh with non-manifold edges or vertices, or inconsistently oriented triangles, into a
/// manifold, consistently oriented one: CGAL's orient_polygon_soup (which cuts the triangles at
/// an edge shared by more than two of them apart and duplicates pinched vertices),
/// polygon_soup_to_polygon_mesh and duplicate_non_manifold_vertices. Expects finite positions,
/// indices in range and no degenerate or duplicate triangles nor unused vertices (geom::repair()
/// removes them first, as CGAL's repair_polygon_soup would, but keeps coincident vertices apart
/// when asked to). Triangles keep their order; vertices keep their indices, copies are appended.
/// Serial; deterministic.
NonManifoldSplit split_non_manifold(TriangleMesh& mesh);

/// What drop_small_components() removed.
struct ComponentDrop {
  std::size_t components = 0;         ///< connected components before
  std::size_t dropped_components = 0; ///< of those, removed
  std::size_t dropped_triangles = 0;
};

/// Removes every connected component (triangles joined by edges) whose area is below
/// `min_area_fraction` times the area of the largest component; the rest keep their order.
/// Expects a manifold mesh. Serial.
ComponentDrop drop_small_components(TriangleMesh& mesh, double min_area_fraction);

/// What fill_holes() added.
struct HoleFill {
  std::size_t holes = 0;           ///< boundary loops closed
  std::size_t added_triangles = 0; ///< triangles of the patches
  std::size_t added_vertices = 0;  ///< inner vertices of the refined patches
};

/// Closes every boundary loop with CGAL's triangulate_and_refine_hole (a minimum-area patch refined
/// to the density around it). Expects a manifold, consistently oriented mesh. Serial.
HoleFill fill_holes(TriangleMesh& mesh);

} // namespace texsim::geom
