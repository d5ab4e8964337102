#include "geom/mesh_repair.hpp"

#include "geom/cgal_surface_mesh.hpp"
#include "geom/mesh_measures.hpp"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <vector>

namespace texsim::geom {
namespace PMP = CGAL::Polygon_mesh_processing;
using cgal::Kernel;
using cgal::SurfaceMesh;

namespace {

/// True when `after` lists the corners of `before` in the opposite cyclic order.
bool reversed(const Triangle& before, const std::vector<std::size_t>& after) {
  for (int shift = 0; shift < 3; ++shift)
    if (std::size_t(before[0]) == after[std::size_t(shift)])
      return std::size_t(before[1]) != after[std::size_t((shift + 1) % 3)];
  return false; // a corner was duplicated: the triangle keeps its order among the copies
}

} // namespace

NonManifoldSplit split_non_manifold(TriangleMesh& mesh) {
  std::vector<Kernel::Point_3> points;
  points.reserve(mesh.positions.size());
  for (const auto& p : mesh.positions)
    points.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(mesh.triangles.size());
  for (const auto& tri : mesh.triangles)
    polygons.push_back({std::size_t(tri[0]), std::size_t(tri[1]), std::size_t(tri[2])});

  // geom::repair() has already done what CGAL's repair_polygon_soup would (drop repeated corners,
  // duplicate triangles and unused points) but without merging coincident points: those may be
  // the copies of an earlier split (a remeshed surface is repaired again), which must stay apart.
  const std::size_t original_points = points.size();
  PMP::orient_polygon_soup(points, polygons);
  TEXSIM_VERIFY(PMP::is_polygon_soup_a_polygon_mesh(polygons),
                "orient_polygon_soup left a soup that is not a manifold polygon mesh");

  NonManifoldSplit split;
  for (std::size_t t = 0; t < polygons.size(); ++t)
    split.reoriented_triangles += reversed(mesh.triangles[t], polygons[t]) ? 1 : 0;

  SurfaceMesh surface;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, surface);
  PMP::duplicate_non_manifold_vertices(surface);
  split.added_vertices = surface.number_of_vertices() - original_points;
  mesh = cgal::to_triangle_mesh(surface, "split_non_manifold");
  return split;
}

ComponentDrop drop_small_components(TriangleMesh& mesh, double min_area_fraction) {
  SurfaceMesh surface = cgal::to_surface_mesh(mesh, "drop_small_components");
  auto component =
      surface.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:component", 0).first;
  ComponentDrop drop;
  drop.components = PMP::connected_components(surface, component);
  if (drop.components < 2)
    return drop;

  // Faces of a Surface_mesh built by to_surface_mesh() are numbered as the input triangles.
  const auto areas = triangle_areas(mesh);
  std::vector<double> component_area(drop.components, 0.0);
  for (const auto f : surface.faces())
    component_area[component[f]] += areas[f.idx()];
  const double threshold =
      min_area_fraction * *std::max_element(component_area.begin(), component_area.end());
  for (const double area : component_area)
    drop.dropped_components += area < threshold ? 1 : 0;

  std::vector<Triangle> kept;
  kept.reserve(mesh.triangles.size());
  for (const auto f : surface.faces())
    if (component_area[component[f]] >= threshold)
      kept.push_back(mesh.triangles[f.idx()]);
  drop.dropped_triangles = mesh.triangles.size() - kept.size();
  mesh.triangles = std::move(kept);
  return drop;
}

HoleFill fill_holes(TriangleMesh& mesh) {
  SurfaceMesh surface = cgal::to_surface_mesh(mesh, "fill_holes");
  std::vector<SurfaceMesh::Halfedge_index> loops;
  PMP::extract_boundary_cycles(surface, std::back_inserter(loops));
  HoleFill fill;
  for (const auto loop : loops) {
    std::vector<SurfaceMesh::Face_index> faces;
    std::vector<SurfaceMesh::Vertex_index> vertices;
    PMP::triangulate_and_refine_hole(surface, loop, std::back_inserter(faces),
                                     std::back_inserter(vertices));
    fill.holes += faces.empty() ? 0 : 1;
    fill.added_triangles += faces.size();
    fill.added_vertices += vertices.size();
  }
  if (fill.holes > 0)
    mesh = cgal::to_triangle_mesh(surface, "fill_holes");
  return fill;
}

} // namespace texsim::geom
