#include "geom/mesh_simplification.hpp"

#include "core/error.hpp"
#include "geom/cgal_surface_mesh.hpp"

#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <cstddef>

namespace texsim::geom {
namespace {

using cgal::SurfaceMesh;

/// Stops the collapse loop once the mesh has at most `target` faces. Counting faces directly
/// (Count_stop_predicate counts edges) makes the target exact for meshes with or without boundary.
class FaceCountStop {
public:
  FaceCountStop(const SurfaceMesh& surface, std::size_t target)
      : surface_(&surface), target_(target) {}

  template <typename Cost, typename Profile>
  bool operator()(const Cost& /*cost*/, const Profile& /*profile*/, std::size_t /*initial_edges*/,
                  std::size_t /*current_edges*/) const {
    return surface_->number_of_faces() <= target_;
  }

private:
  const SurfaceMesh* surface_;
  std::size_t target_;
};

} // namespace

TriangleMesh simplify(const TriangleMesh& mesh, std::size_t target_triangles) {
  if (mesh.triangles.size() <= target_triangles) {
    return mesh;
  }
  auto surface = cgal::to_surface_mesh(mesh, "simplify");
  CGAL::Surface_mesh_simplification::edge_collapse(surface,
                                                   FaceCountStop(surface, target_triangles));
  surface.collect_garbage();
  return cgal::to_triangle_mesh(surface, "simplify");
}

} // namespace texsim::geom
