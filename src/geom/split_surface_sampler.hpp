#pragma once
/// A vector field given at the vertices of a surface whose triangles are split over the ranks
/// (each rank its share, e.g. DistributedTriangles::owned_surface()), read at points that rank 0
/// holds: the piecewise-linear interpolant at the nearest point of the whole surface. No rank
/// gathers the surface or builds a tree over more than its share.
///
/// Each rank builds an AabbTree over its share, and the shares' bounding boxes are allgathered
/// (a table of 6 doubles per rank). Rank 0 asks for each point, first, the rank whose box is
/// nearest; that rank's nearest triangle bounds the distance, and the point then goes to every
/// other rank whose box lies within the bound. Ranks answer by AabbTree::nearest_triangle's rule
/// (smallest squared distance, ties to the smallest triangle id) and rank 0 keeps the best answer
/// by the same rule, so the triangle, and the value's bits, are those of one tree over the whole
/// surface whatever the split: the same bytes at any rank count.
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

/// `share`: this rank's triangles (any may have none) and `triangle_ids[k]`, the id of its
/// triangle k in the whole surface, increasing. `values[v]`: the field at the share's vertex v.
/// `points`: rank 0's query points (the others pass none). Returns, on rank 0, the field at each
/// point: w_a f_a + w_b f_b + w_c f_c over the nearest triangle's corners, w the barycentric
/// weights of the point's projection onto it (geom::barycentric_weights); empty on the other
/// ranks. Throws texsim::Error on every rank when no rank has a triangle. Collective.
std::vector<std::array<double, 3>>
sample_split_surface(const par::Comm& comm, const TriangleMesh& share,
                     std::span<const std::int64_t> triangle_ids,
                     std::span<const std::array<double, 3>> values, std::span<const Vec3> points);

} // namespace texsim::geom
