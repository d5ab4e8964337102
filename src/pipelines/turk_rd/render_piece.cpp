#include "pipelines/turk_rd/render_piece.hpp"

#include "core/error.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/patch_refinement.hpp"
#include "par/collective.hpp"

#include <algorithm>
#include <array>
#include <string>

namespace texsim::pipelines::turk_rd {

RenderPiece make_render_piece(const par::Comm& comm, const geom::DistributedTriangles& input,
                              int subdivision_levels) {
  RenderPiece piece;
  // Each rank refines only its share of the input (the input triangles of its run along a Morton
  // curve of their centroids) and one ring of input triangles around it. The fine triangles one
  // fine edge out of the share lie in that ring at least n - 1 fine edges (n = 2^levels) inside
  // its border, where Loop's masks already give the whole surface's positions: the normals at the
  // piece's border see all their triangles, exactly (render_piece_test checks the bits).
  // The ring's vertices lie within one edge of the share's corners, and their triangles within
  // two: a window of that reach holds every triangle around every vertex of the patch, so the cut
  // sees the whole mesh's neighbourhoods.
  const geom::LocalSurface& own = input.owned_surface();
  std::vector<geom::Vec3> corners;
  for (const auto& t : own.mesh.triangles)
    for (const std::int32_t v : t)
      corners.push_back(own.mesh.positions[std::size_t(v)]);
  const geom::LocalSurface window = input.window(comm, corners, 2.5 * input.longest_edge());
  const geom::MeshTopology window_topology(window.mesh);
  std::vector<char> creases = geom::edge_flags(window_topology, window.triangle_creases);
  if (std::none_of(creases.begin(), creases.end(), [](char c) { return c != 0; }))
    creases.clear();
  std::vector<std::int32_t> share;
  for (const std::int64_t id : own.triangle_ids)
    share.push_back(window.local_triangle(id));
  std::vector<std::int32_t> ring_of;
  const geom::CoarsePatch patch =
      geom::PatchCutter(window.mesh, window_topology, creases).cut(share, 1, &ring_of);
  geom::RefinedPatch fine;
  par::run_collectively(comm, [&] {
    try {
      fine = geom::refine_patch(patch,
                                std::vector<geom::RefinementStep>(std::size_t(subdivision_levels)));
    } catch (const Error& error) {
      throw InputError(std::string("turk_rd.render.subdivision_levels: this mesh cannot be "
                                   "Loop-subdivided (") +
                       error.what() + "); use 0");
    }
  });
  const geom::MeshTopology topology(fine.mesh);
  std::vector<std::int32_t> triangles;
  std::vector<char> taken(fine.mesh.triangles.size(), 0);
  for (std::size_t t = 0; t < fine.mesh.triangles.size(); ++t)
    if (ring_of[fine.parent[t]] == 0) {
      triangles.push_back(std::int32_t(t));
      taken[t] = 1;
    }
  piece.written_triangles = triangles.size();
  for (std::size_t k = 0; k < piece.written_triangles; ++k)
    for (const auto v : fine.mesh.triangles[triangles[k]])
      for (const auto t : topology.vertex_triangles().row(v))
        if (!taken[t]) {
          taken[t] = 1;
          triangles.push_back(t);
        }

  std::vector<std::int32_t> local_of(fine.mesh.positions.size(), -1);
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    geom::Triangle local{};
    for (int c = 0; c < 3; ++c) {
      const auto v = fine.mesh.triangles[triangles[k]][c];
      if (local_of[v] < 0) {
        local_of[v] = piece.mesh.num_vertices();
        piece.mesh.positions.push_back(fine.mesh.positions[v]);
      }
      local[c] = local_of[v];
    }
    piece.mesh.triangles.push_back(local);
  }
  std::vector<std::int32_t> written_index(piece.mesh.positions.size(), -1);
  for (std::size_t k = 0; k < piece.written_triangles; ++k)
    for (const auto v : piece.mesh.triangles[k]) {
      if (written_index[v] < 0) {
        written_index[v] = std::int32_t(piece.written_vertices.size());
        piece.written_vertices.push_back(v);
      }
      piece.written_connectivity.push_back(written_index[v]);
    }

  return piece;
}

} // namespace texsim::pipelines::turk_rd
