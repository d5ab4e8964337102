#include "geom/lscm_parameterization.hpp"

#include "core/error.hpp"
#include "geom/cgal_surface_mesh.hpp"
#include "geom/mesh_topology.hpp"

#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

#include <cstddef>
#include <vector>

namespace texsim::geom {
namespace {

namespace SMP = CGAL::Surface_mesh_parameterization;
using cgal::SurfaceMesh;

constexpr const char* kCaller = "lscm_parameterize";

/// Number of boundary loops of `surface` and one border halfedge on the last loop found.
struct BorderLoops {
  std::size_t count = 0;
  SurfaceMesh::Halfedge_index halfedge;
};

BorderLoops border_loops(const SurfaceMesh& surface) {
  BorderLoops loops;
  std::vector<bool> visited(surface.number_of_halfedges(), false);
  for (const auto h : surface.halfedges()) {
    if (!surface.is_border(h) || visited[h.idx()]) {
      continue;
    }
    ++loops.count;
    loops.halfedge = h;
    auto walk = h;
    do {
      visited[walk.idx()] = true;
      walk = surface.next(walk);
    } while (walk != h);
  }
  return loops;
}

} // namespace

std::vector<Eigen::Vector2d> lscm_parameterize(const TriangleMesh& disk) {
  TEXSIM_VERIFY(disk.num_triangles() > 0, kCaller << ": the mesh has no triangles");
  const MeshTopology topo(disk);
  TEXSIM_VERIFY(topo.is_manifold(), kCaller << ": the mesh is not manifold ("
                                            << topo.non_manifold_edges().size() << " edges, "
                                            << topo.non_manifold_vertices().size()
                                            << " vertices); a topological disk is required");
  TEXSIM_VERIFY(topo.isolated_vertices().empty(),
                kCaller << ": the mesh has " << topo.isolated_vertices().size()
                        << " isolated vertices; a topological disk is required");
  auto surface = cgal::to_surface_mesh(disk, kCaller);

  const auto loops = border_loops(surface);
  TEXSIM_VERIFY(loops.count == 1, kCaller << ": the mesh has " << loops.count
                                          << " boundary loops, a topological disk has exactly one");
  const std::size_t components = CGAL::Polygon_mesh_processing::connected_components(
      surface, surface.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:component").first);
  TEXSIM_VERIFY(components == 1, kCaller << ": the mesh has " << components
                                         << " connected components, a topological disk has one");
  TEXSIM_VERIFY(topo.euler_characteristic() == 1,
                kCaller << ": the mesh has Euler characteristic " << topo.euler_characteristic()
                        << " (handles), a topological disk has 1");

  auto uv =
      surface.add_property_map<SurfaceMesh::Vertex_index, cgal::Kernel::Point_2>("v:uv").first;
  const SMP::Error_code status =
      SMP::parameterize(surface, SMP::LSCM_parameterizer_3<SurfaceMesh>(), loops.halfedge, uv);
  TEXSIM_VERIFY(status == SMP::OK,
                kCaller << ": CGAL LSCM failed with status " << SMP::get_error_message(status));

  std::vector<Eigen::Vector2d> out(disk.positions.size());
  for (const auto v : surface.vertices()) {
    out[v.idx()] = Eigen::Vector2d(uv[v].x(), uv[v].y());
  }
  return out;
}

} // namespace texsim::geom
