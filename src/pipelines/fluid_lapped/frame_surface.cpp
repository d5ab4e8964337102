#include "pipelines/fluid_lapped/frame_surface.hpp"

#include "geom/mesh_measures.hpp"

namespace texsim::pipelines::fluid_lapped {

FrameSurface::FrameSurface(geom::TriangleMesh surface)
    : mesh(std::move(surface)), topology(mesh), tree(mesh),
      triangle_normals(geom::triangle_normals(mesh)),
      mean_edge_length(geom::mean_edge_length(mesh)) {}

} // namespace texsim::pipelines::fluid_lapped
