#pragma once
/// Exact restricted Voronoi diagram (RVD) of seed points on a triangle mesh: the 3D Euclidean
/// Voronoi cells of the seeds intersected with the triangles (Yan, Levy, Liu, Sun, Wang, "Isotropic
/// remeshing with fast and exact computation of restricted Voronoi diagram", SGP 2009). Each
/// triangle is split into convex pieces, one per seed whose cell meets it, with the piece's area
/// and the lengths of its borders with the other cells. Used by Turk's reaction-diffusion on
/// arbitrary surfaces (cell area, neighbours, diffusion coefficient = border length / seed
/// distance).
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace texsim::geom {

/// One triangle's part of one seed's cell.
struct VoronoiPiece {
  std::int32_t triangle = -1; ///< mesh triangle id
  std::int32_t seed = -1;     ///< index into the seeds span
  double area = 0.0;          ///< model units squared, > 0
  /// (other seed index, length of the border between the two cells inside this triangle), sorted by
  /// seed index; borders along mesh edges/boundaries are not listed. Model units.
  std::vector<std::pair<std::int32_t, double>> borders;
  std::vector<Vec3>
      polygon; ///< the clipped convex polygon's vertices in order (only when keep_polygons)
  /// Parallel to `polygon` (only when keep_polygons): label k belongs to the edge polygon[k] ->
  /// polygon[k + 1 mod n] and is the index (into the seeds span) of the other seed whose bisector
  /// made that edge, or -1 when the edge lies on the triangle's boundary. The polygon runs in the
  /// triangle's corner order, so a vertex between edges labelled a then b is where the cells of
  /// (seed, a, b) meet, counter-clockwise in that order seen from the side the triangle faces.
  std::vector<std::int32_t> edge_labels;
};

/// The pieces of every triangle in `triangles`: each triangle split exactly into the parts closest
/// to each seed (pieces of zero area are left out). `seeds` are points in model units (usually on
/// the surface); `seed_ids` (same length, all different) are global ids used ONLY to break ties
/// deterministically: neighbours are taken in (distance, id) order, and a point equidistant from
/// two seeds within the plane of a whole piece goes to the smaller id. So a rank that holds extra
/// far-away seeds, or the seeds in another order, gets bit-identical pieces (up to the seed
/// indices). Result sorted by (triangle, seed id).
///
/// A piece is certified by the security radius: every seed closer to its seed than twice the
/// piece's radius (farthest polygon vertex) has clipped it. For a rank's part of a mesh, the pieces
/// are those computed with all seeds when `seeds` holds every seed within 3 rho of the rank's
/// triangles, rho being the largest distance from a surface point to its nearest seed (to the bit
/// in practice; a seed left out could only change round-off, by being the first to clip a large
/// part of a triangle that nearer seeds clip again later).
///
/// Throws texsim::Error when a cell cannot be certified (its security radius not reached with all
/// given seeds), meaning the caller's halo of seeds was too small (with the complete seed set this
/// only happens for a handful of seeds: no other seed lies beyond twice a cell's radius), and when
/// a triangle id is out of range or repeated, seed ids repeat, a seed is not finite, or the seeds
/// are empty while triangles are not. OpenMP over triangles; the result does not depend on the
/// thread count. Not collective.
std::vector<VoronoiPiece> restricted_voronoi_pieces(const TriangleMesh& mesh,
                                                    std::span<const std::int32_t> triangles,
                                                    std::span<const Vec3> seeds,
                                                    std::span<const std::int64_t> seed_ids,
                                                    bool keep_polygons);

} // namespace texsim::geom
