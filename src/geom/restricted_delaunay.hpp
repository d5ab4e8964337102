#pragma once
/// The restricted Delaunay triangulation of points on a surface: the dual of their restricted
/// Voronoi diagram (restricted_voronoi.hpp), one triangle for every point of the surface where
/// three cells meet. How Turk's retiling ("Re-tiling polygonal surfaces", SIGGRAPH '92) and
/// Wei-Levoy's mesh pyramid (SIGGRAPH '01, Section 3.1) turn evenly spread points into a mesh whose
/// vertices are those points.
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <span>

namespace texsim::geom {

/// restricted_delaunay's default chunk: the polygons of this many triangles at a time.
inline constexpr std::int32_t kRestrictedDelaunayChunk = 1 << 16;

/// Vertex i of the result is seeds[i] (same order). A triangle joins the seeds whose cells meet at
/// a vertex of the restricted Voronoi diagram inside `surface` (a polygon vertex of a piece between
/// two bisector edges, VoronoiPiece::edge_labels), counter-clockwise seen from the side the
/// surface triangle holding that point faces. `seed_ids` (all different) only break ties, as in
/// restricted_voronoi_pieces(); the triangles are written starting at their smallest-id vertex and
/// sorted by their ids, so the result depends on neither the thread count nor the order of the
/// surface's triangles, and permuting the seeds (with their ids) only renumbers the vertices.
///
/// A seed's 3D Voronoi cell may meet the surface in several connected components (the surface
/// folds back into it near creases, saddles and thin parts). Its largest component (by area; exact
/// ties: the first in (triangle, seed id) order) keeps the seed; every other component is handed to
/// the neighbouring cell that shares the longest border with it (ties: smaller id), as if that
/// cell reached there, so the triangles are those of a tiling by connected cells. Pieces of one
/// seed in two triangles are connected when both touch their shared edge along a segment.
///
/// Degenerate cases, decided here:
/// - Four or more cells meeting at one point (cocircular seeds, e.g. a square lattice): every seed
///   whose squared distance to the point is within 1e-9 (|p|_inf + r) r of the owning seed's
///   (r = that seed's distance, round-off of the clipped vertex being far smaller) takes part;
///   they are ordered counter-clockwise around the point in the surface triangle's plane and split
///   as a fan from the smallest id. Every cell that sees the point finds the same fan, so the
///   split is consistent.
/// - The same three seeds met more than once (a triple of cells meeting at two points, or one point
///   seen from both triangles of an edge it lies on): one triangle, oriented as most sightings say
///   (ties: the orientation of the ids in increasing order). Met with opposite orientations, the
///   triple marks a Voronoi edge piercing the surface twice (cells wrapping around a sharp corner
///   or a part thinner than the spacing): the result is then usually not a manifold.
/// - A point where three cells meet exactly on a surface vertex, so that no piece has a corner
///   between two bisector edges there, gives no triangle; nor does a meeting point that round-off
///   puts outside both triangles of the edge it lies near. Both need seeds placed on purpose (or a
///   1e-16-relative coincidence); the caller's manifold check (MeshTopology) reports the hole.
/// It does not check manifoldness. Throws what restricted_voronoi_pieces() throws (repeated ids,
/// non-finite seeds, cells not certified). OpenMP inside; not collective.
///
/// The pieces are computed `chunk_triangles` triangles at a time and reduced to what the dual
/// needs (about 32 bytes a piece, plus its borders and meetings), so the polygons of the whole
/// surface are never held at once; the result does not depend on the chunk size.
TriangleMesh restricted_delaunay(const TriangleMesh& surface, std::span<const Vec3> seeds,
                                 std::span<const std::int64_t> seed_ids,
                                 std::int32_t chunk_triangles = kRestrictedDelaunayChunk);

/// What a rank cut its triangles against in the parallel restricted_delaunay.
struct SeedHaloReport {
  std::int64_t seeds = 0;  ///< its own seeds and the halo's, or every seed
  bool every_seed = false; ///< some rank's check failed: every rank cut against every seed
};

/// The same result on rank 0 (an empty mesh on the others), computed by every rank. Rank 0 alone
/// holds `root_surface` (the others pass an empty mesh); each rank passes its run of the seeds
/// (`run_seeds`, their ids `run_ids`): vertex i of the result is the i-th seed of the runs in rank
/// order. Rank 0 puts its triangles in order along a Morton curve of their centroids and sends
/// every rank an equal run of that order as corner positions; each rank cuts them into Voronoi
/// pieces (most of the work) against its own seeds and the other ranks' within `halo` of its
/// triangles. That is exactly the cut against every seed when 3 R <= halo, R the largest piece
/// radius (farthest polygon vertex from the piece's seed): a seed that clips a piece of triangle
/// T, or that the cut asks before it certifies the piece, lies within 2 (R + E) of the piece's
/// seed (E: T's longest edge), and the halo around T is grown by E too. Each rank checks it on
/// the pieces it cut; when any rank's check fails, or its seeds cannot certify a cell, every rank
/// cuts again against every seed (gathered on every rank). Rank 0 then gathers the pieces'
/// summaries (without their borders: it asks the cutting ranks for the borders of the pieces it
/// hands over only) and the seeds and joins them as above, on the surface in curve order: the
/// result does not depend on the rank count, and is the serial one (which does not depend on the
/// triangles' order). A failure on any rank throws on every rank. `report`, when given, says what
/// this rank cut against. Collective.
TriangleMesh restricted_delaunay(const par::Comm& comm, const TriangleMesh& root_surface,
                                 std::span<const Vec3> run_seeds,
                                 std::span<const std::int64_t> run_ids, double halo,
                                 std::int32_t chunk_triangles = kRestrictedDelaunayChunk,
                                 SeedHaloReport* report = nullptr);

} // namespace texsim::geom
