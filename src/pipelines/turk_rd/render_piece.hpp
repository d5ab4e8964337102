#pragma once
/// This rank's share of the surface turk_rd renders its pattern on: the input mesh, Loop-refined
/// `render.subdivision_levels` times on the rank's share only (geom::refine_patch), never whole
/// on any rank. The shares are runs of input triangles along a Morton curve of their centroids;
/// each rank writes the fine triangles inside its share and keeps the ring of fine triangles
/// around them, so normals at the piece's border see all their triangles.
#include "geom/distributed_triangles.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::turk_rd {

struct RenderPiece {
  geom::TriangleMesh mesh;           ///< written triangles first, then the surrounding ring
  std::size_t written_triangles = 0; ///< how many of mesh.triangles are written
  std::vector<std::int32_t> written_vertices;     ///< local vertices of the written triangles
  std::vector<std::int64_t> written_connectivity; ///< 3 indices into written_vertices each
};

/// The piece of this rank: its share of `input` (DistributedTriangles' share) refined, the
/// input's crease flags kept sharp. Every fine triangle is written by exactly one rank, with the
/// position bits of geom::refine on the whole input. InputError (on every rank) when the input
/// cannot be Loop-subdivided. Collective.
RenderPiece make_render_piece(const par::Comm& comm, const geom::DistributedTriangles& input,
                              int subdivision_levels);

} // namespace texsim::pipelines::turk_rd
