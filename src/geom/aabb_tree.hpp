#pragma once
/// Closest-point queries on a triangle surface (CGAL AABB tree).
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <memory>
#include <optional>

namespace texsim::geom {

/// Closest point of the surface to a query, and the triangle holding it.
struct ClosestPoint {
  Vec3 point;            ///< on the surface, model units
  std::int32_t triangle; ///< index into the mesh's triangles
  double distance;       ///< from the query to `point`, model units
};

/// The nearest triangle as nearest_triangle() ranks them.
struct NearestTriangle {
  Vec3 point;              ///< the query's projection onto the triangle (CGAL's)
  std::int32_t triangle;   ///< index into the mesh's triangles
  double squared_distance; ///< from the query to `point`, as CGAL measures it
};

/// Where a line crosses a triangle: origin + t * direction.
struct LineCrossing {
  std::int32_t triangle; ///< index into the mesh's triangles
  double t;
};

/// Bounding-volume hierarchy over a mesh's triangles for projecting points onto the surface. Keeps
/// a copy of the geometry (the mesh may be destroyed afterwards). Queries are const and may run
/// concurrently from several threads. Serial build, not collective.
class AabbTree {
public:
  /// Builds the tree; throws texsim::Error when the mesh has no triangles.
  explicit AabbTree(const TriangleMesh& mesh);
  ~AabbTree();
  AabbTree(AabbTree&&) noexcept;
  AabbTree& operator=(AabbTree&&) noexcept;

  /// The point of the surface nearest to `query`.
  ClosestPoint closest_point(const Vec3& query) const;

  /// The triangle nearest to `query` by one rule that no tree shape changes: the smallest
  /// squared distance from the query to the triangle's projected point, ties to the smallest
  /// triangle id. closest_point() settles ties by its traversal order instead, so two trees over
  /// overlapping or split sets of triangles may disagree on equally near triangles (a point above
  /// a shared edge or corner); with this rule, the nearest over a union is the nearest of the
  /// parts' answers, by the same rule. Thread-safe.
  NearestTriangle nearest_triangle(const Vec3& query) const;

  /// Where the line origin + t * direction (t of either sign) crosses the surface nearest to
  /// `origin`: the smallest |t|, ties to the smaller triangle id; `distance` is |t| |direction|.
  /// A triangle is hit when the crossing of its plane has barycentric coordinates >= -1e-12 (its
  /// edges and corners belong to it, so a line through an edge is not lost between two
  /// triangles); triangles parallel to the line (sine of the angle below 1e-12) are not hit.
  /// std::nullopt when the line misses, or `direction` is zero. How Wei-Levoy find a vertex's
  /// parent face on a coarser mesh level (the line along +-n_p). Thread-safe.
  std::optional<ClosestPoint> nearest_line_hit(const Vec3& origin, const Vec3& direction) const;
  /// The same crossing as the line parameter t (the hit is origin + t * direction), for callers
  /// that compare hits found in several trees by nearest_line_hit's rule. Thread-safe.
  std::optional<LineCrossing> nearest_line_crossing(const Vec3& origin,
                                                    const Vec3& direction) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace texsim::geom
