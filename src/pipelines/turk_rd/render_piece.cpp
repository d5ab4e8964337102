#include "pipelines/turk_rd/render_piece.hpp"

#include "core/error.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/morton_order.hpp"
#include "geom/patch_refinement.hpp"
#include "par/collective.hpp"

#include <array>
#include <string>

namespace texsim::pipelines::turk_rd {

RenderPiece make_render_piece(const par::Comm& comm, const geom::TriangleMesh& input_mesh,
                              std::span<const char> creases, int subdivision_levels) {
  RenderPiece piece;
  // Each rank refines only its share of the input (the input triangles of its run along a Morton
  // curve of their centroids) and one ring of input triangles around it. The fine triangles one
  // fine edge out of the share lie in that ring at least n - 1 fine edges (n = 2^levels) inside
  // its border, where Loop's masks already give the whole surface's positions: the normals at the
  // piece's border see all their triangles, exactly (render_piece_test checks the bits).
  const geom::MeshTopology input_topology(input_mesh);
  const auto part = geom::morton_triangle_parts(input_mesh, comm.size);
  std::vector<std::int32_t> share;
  for (std::size_t t = 0; t < part.size(); ++t)
    if (part[t] == comm.rank)
      share.push_back(std::int32_t(t));
  std::vector<std::int32_t> ring_of;
  const geom::CoarsePatch patch =
      geom::PatchCutter(input_mesh, input_topology, creases).cut(share, 1, &ring_of);
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
