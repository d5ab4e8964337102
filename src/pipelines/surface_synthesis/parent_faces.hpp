#pragma once
/// Wei-Levoy Section 3.3: "for each vertex p of pyramid G_s, we first find the corresponding parent
/// faces at lower resolution pyramid levels by intersecting the normal n of p with the coarse
/// meshes". The coarser part of p's neighbourhood grows from that face, and a finer level's
/// orientation starts from the directions at its corners.
#include "geom/aabb_tree.hpp"
#include "par/comm.hpp"
#include "pipelines/surface_synthesis/orientation_field.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// For each point (with its unit normal): the triangle of `coarse` first hit by the line through
/// the point along +-normal (nearest intersection on either side) and the barycentric weights of
/// the hit; not found (vertices[0] == -1) when the line misses the coarse surface (Wei-Levoy
/// footnote 2: the coarser part is then left uncovered). OpenMP; deterministic.
std::vector<ParentFace> find_parent_faces(std::span<const geom::Vec3> points,
                                          std::span<const geom::Vec3> normals,
                                          const geom::TriangleMesh& coarse,
                                          const geom::AabbTree& coarse_tree);

/// The faces of this rank's run [rank_offsets[r], rank_offsets[r + 1]) of the points (vertex
/// rank_offsets[r] + i at i; `normals` are the run's), searched with the rank's own tree of
/// `coarse` (dropped on return): the serial call's records for those points, the same bytes. No
/// rank holds another's run: every reader of a parent face (orientation, stencils) works on its own
/// vertices. Sends no messages.
std::vector<ParentFace> find_parent_faces(const par::Comm& comm,
                                          std::span<const std::int64_t> rank_offsets,
                                          std::span<const geom::Vec3> points,
                                          std::span<const geom::Vec3> normals,
                                          const geom::TriangleMesh& coarse);

} // namespace texsim::pipelines::surface_synthesis
