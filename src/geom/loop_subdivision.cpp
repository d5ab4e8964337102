#include "geom/loop_subdivision.hpp"

#include "core/error.hpp"
#include "geom/cgal_surface_mesh.hpp"

#include <CGAL/subdivision_method_3.h>

namespace texsim::geom {

TriangleMesh loop_subdivide(const TriangleMesh& mesh, int levels) {
  TEXSIM_VERIFY(levels >= 0, "loop_subdivide: levels " << levels << " must be >= 0");
  auto surface = cgal::to_surface_mesh(mesh, "loop_subdivide");
  CGAL::Subdivision_method_3::Loop_subdivision(surface,
                                               CGAL::parameters::number_of_iterations(levels));
  surface.collect_garbage();
  return cgal::to_triangle_mesh(surface, "loop_subdivide");
}

} // namespace texsim::geom
