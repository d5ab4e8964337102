#pragma once
/// Conversion between TriangleMesh and CGAL::Surface_mesh, shared by the CGAL-backed algorithms.
/// Internal: include only from the .cpp files that already compile CGAL, never from a public
/// header.
#include "core/error.hpp"
#include "geom/triangle_mesh.hpp"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <cstddef>
#include <string_view>

namespace texsim::geom::cgal {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

/// Copies `mesh` into a Surface_mesh; vertex i of `mesh` becomes Vertex_index(i). Throws
/// texsim::Error, prefixed with `caller`, when a triangle breaks edge-manifoldness or orientation.
inline SurfaceMesh to_surface_mesh(const TriangleMesh& mesh, std::string_view caller) {
  SurfaceMesh surface;
  surface.reserve(mesh.positions.size(), 3 * mesh.triangles.size() / 2, mesh.triangles.size());
  for (const auto& p : mesh.positions) {
    surface.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z()));
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const auto face =
        surface.add_face(SurfaceMesh::Vertex_index(tri[0]), SurfaceMesh::Vertex_index(tri[1]),
                         SurfaceMesh::Vertex_index(tri[2]));
    TEXSIM_VERIFY(face != SurfaceMesh::null_face(),
                  caller << ": triangle " << t << " breaks manifoldness or orientation");
  }
  return surface;
}

/// Copies a triangulated Surface_mesh without removed elements (call collect_garbage() first) back
/// into a TriangleMesh with the same vertex and face order.
inline TriangleMesh to_triangle_mesh(const SurfaceMesh& surface, std::string_view caller) {
  TEXSIM_VERIFY(!surface.has_garbage(), caller << ": Surface_mesh still holds removed elements");
  TriangleMesh out;
  out.positions.reserve(surface.number_of_vertices());
  for (const auto v : surface.vertices()) {
    const auto& p = surface.point(v);
    out.positions.emplace_back(p.x(), p.y(), p.z());
  }
  out.triangles.reserve(surface.number_of_faces());
  for (const auto f : surface.faces()) {
    Triangle tri;
    int corner = 0;
    for (const auto v : surface.vertices_around_face(surface.halfedge(f))) {
      TEXSIM_VERIFY(corner < 3, caller << ": CGAL returned a face that is not a triangle");
      tri[corner++] = static_cast<std::int32_t>(v.idx());
    }
    TEXSIM_VERIFY(corner == 3, caller << ": CGAL returned a face that is not a triangle");
    out.triangles.push_back(tri);
  }
  return out;
}

} // namespace texsim::geom::cgal
