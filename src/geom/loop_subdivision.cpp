#include "geom/loop_subdivision.hpp"

#include "core/error.hpp"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/subdivision_method_3.h>

#include <vector>

namespace texsim::geom {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

} // namespace

TriangleMesh loop_subdivide(const TriangleMesh& mesh, int levels) {
  TEXSIM_VERIFY(levels >= 0, "loop_subdivide: levels " << levels << " must be >= 0");
  SurfaceMesh surface;
  std::vector<SurfaceMesh::Vertex_index> vertex(mesh.positions.size());
  for (std::size_t v = 0; v < vertex.size(); ++v) {
    const auto& p = mesh.positions[v];
    vertex[v] = surface.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z()));
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const auto face = surface.add_face(vertex[tri[0]], vertex[tri[1]], vertex[tri[2]]);
    TEXSIM_VERIFY(face != SurfaceMesh::null_face(),
                  "loop_subdivide: triangle " << t << " breaks manifoldness or orientation");
  }
  CGAL::Subdivision_method_3::Loop_subdivision(surface,
                                               CGAL::parameters::number_of_iterations(levels));
  surface.collect_garbage();

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
      TEXSIM_VERIFY(corner < 3, "loop_subdivide: CGAL returned a face that is not a triangle");
      tri[corner++] = static_cast<std::int32_t>(v.idx());
    }
    out.triangles.push_back(tri);
  }
  return out;
}

} // namespace texsim::geom
