#include "geom/mesh_remesh.hpp"

#include "geom/cgal_surface_mesh.hpp"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <iterator>
#include <vector>

namespace texsim::geom {
namespace PMP = CGAL::Polygon_mesh_processing;
using cgal::SurfaceMesh;

TriangleMesh remesh_isotropic(const TriangleMesh& mesh, const RemeshOptions& options) {
  TEXSIM_VERIFY(options.edge_length > 0 && options.iterations > 0,
                "remesh_isotropic: edge length " << options.edge_length << ", iterations "
                                                 << options.iterations);
  SurfaceMesh surface = cgal::to_surface_mesh(mesh, "remesh_isotropic");
  // Protected edges must not be longer than 4/3 of the target, or the remesher cannot keep them.
  std::vector<SurfaceMesh::Edge_index> border;
  std::vector<SurfaceMesh::Halfedge_index> border_halfedges;
  PMP::border_halfedges(faces(surface), surface, std::back_inserter(border_halfedges));
  for (const auto h : border_halfedges)
    border.push_back(edge(h, surface));
  PMP::split_long_edges(border, options.edge_length, surface);
  PMP::isotropic_remeshing(
      faces(surface), options.edge_length, surface,
      PMP::parameters::number_of_iterations(options.iterations).protect_constraints(true));
  surface.collect_garbage();
  return cgal::to_triangle_mesh(surface, "remesh_isotropic");
}

} // namespace texsim::geom
