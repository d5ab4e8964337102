#pragma once
/// Moving points along a triangle surface: a straight path within a triangle, unfolded across
/// edges into the neighbouring triangle's plane (a discrete geodesic), as in Turk's point
/// relaxation (SIGGRAPH '91).
#include "geom/mesh_topology.hpp"
#include "geom/surface_point.hpp"
#include "geom/triangle_mesh.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace texsim::geom {

/// Per-triangle frames and edge neighbours, built once; move() is const and thread-safe. Keeps
/// its own copy of what it needs (mesh and topology may be destroyed afterwards). Serial, not
/// collective.
class SurfaceWalker {
public:
  /// Edge crossings one move() may make before it stops where it is (guards against a path
  /// circling a vertex through rounding).
  static constexpr int kMaxCrossings = 1000;

  /// `topology` must be built from `mesh`. Triangles whose corners are (almost) collinear
  /// (sine of the corner angle below 1e-7) act as walls: a path stops on their edges, and a point
  /// on one does not move.
  SurfaceWalker(const TriangleMesh& mesh, const MeshTopology& topology);

  /// Moves p by `displacement` along the surface: the displacement is projected into p's
  /// triangle plane; when the straight path leaves the triangle through an edge shared with
  /// exactly one other triangle, the rest of the path is rotated about that edge into the
  /// neighbour's plane (unfolding) and the walk continues; at a boundary or non-manifold edge the
  /// point stops on the edge. The length travelled equals the length of the projected
  /// displacement unless the walk stops early. p.position is first projected onto its triangle
  /// (nearest point in the plane, then barycentric coordinates clamped). The result lies on its
  /// triangle (barycentric coordinates >= 0, summing to 1, up to rounding of the final
  /// combination of corners). At most kMaxCrossings edge crossings.
  SurfacePoint move(const SurfacePoint& p, const Vec3& displacement) const;

  /// Barycentric coordinates of the orthogonal projection of `position` into the plane of
  /// `triangle`, weights of its corners 0, 1, 2 (not clamped; zeros for a wall triangle).
  std::array<double, 3> barycentric(std::int32_t triangle, const Vec3& position) const;

  /// The triangle across edge `corner` (the edge opposite that corner) of `triangle`, or -1 when
  /// the edge is a boundary, non-manifold, or borders a wall triangle.
  std::int32_t neighbor(std::int32_t triangle, int corner) const {
    return faces_[triangle].neighbor[corner];
  }

  std::int32_t num_triangles() const { return static_cast<std::int32_t>(faces_.size()); }

private:
  struct Face {
    std::array<Vec3, 3> corner;
    /// Gradients of barycentric coordinates 1 and 2 (coordinate 0 is 1 minus both).
    Vec3 grad1 = Vec3::Zero(), grad2 = Vec3::Zero();
    Vec3 normal = Vec3::Zero();
    std::array<std::int32_t, 3> vertex{-1, -1, -1};
    std::array<std::int32_t, 3> neighbor{-1, -1, -1};
    /// Corner of the neighbour opposite the shared edge.
    std::array<std::int8_t, 3> neighbor_corner{-1, -1, -1};
    bool wall = false;
  };

  std::vector<Face> faces_;
};

} // namespace texsim::geom
