#pragma once
/// Wei-Levoy Section 3.3: "for each vertex p of pyramid G_s, we first find the corresponding parent
/// faces at lower resolution pyramid levels by intersecting the normal n of p with the coarse
/// meshes". The coarser part of p's neighbourhood grows from that face, and a finer level's
/// orientation starts from the directions at its corners.
#include "geom/aabb_tree.hpp"
#include "geom/distributed_triangles.hpp"
#include "par/comm.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"
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

/// Where a rank looks first for its points' parent faces: the triangles of the coarser level
/// within two of its spacings. A vertex lies within a fraction of a spacing of the coarser surface,
/// so nearly every hit is found there.
inline double parent_window_reach(double coarse_spacing) {
  return 2.0 * coarse_spacing;
}

/// The faces of this rank's `points` (with their unit `normals`) on the coarser level split over
/// the ranks: the serial call's records on the whole level, the same bytes. Each rank searches a
/// window of the level (the triangles within `reach` of its points, DistributedTriangles::window);
/// a hit nearer than `reach` is the nearest on the whole level, since every nearer crossing lies
/// within `reach` too. The points it cannot vouch for (a miss, or a hit farther away) go to every
/// rank, which searches its own share, and the nearest crossing (ties to the smaller triangle id,
/// as AabbTree) comes back. No rank holds the whole level. Collective.
std::vector<ParentFace> find_parent_faces(const par::Comm& comm, std::span<const geom::Vec3> points,
                                          std::span<const geom::Vec3> normals,
                                          const geom::DistributedTriangles& coarse, double reach);

/// The same for this rank's run of `level` on `coarser`'s triangles, with windows of
/// parent_window_reach(coarser.spacing). Collective.
std::vector<ParentFace> find_parent_faces(const par::Comm& comm, const RetiledLevel& level,
                                          const RetiledLevel& coarser);

} // namespace texsim::pipelines::surface_synthesis
