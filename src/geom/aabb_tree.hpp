#pragma once
/// Closest-point queries on a triangle surface (CGAL AABB tree).
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <memory>

namespace texsim::geom {

/// Closest point of the surface to a query, and the triangle holding it.
struct ClosestPoint {
  Vec3 point;            ///< on the surface, model units
  std::int32_t triangle; ///< index into the mesh's triangles
  double distance;       ///< from the query to `point`, model units
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

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace texsim::geom
