#pragma once
/// The plain triangle-surface container every geom algorithm reads and writes.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace texsim::geom {

/// A point or vector in 3D (model units).
using Vec3 = Eigen::Vector3d;

/// Vertex ids of one triangle, counter-clockwise seen from the outside of an oriented surface.
using Triangle = std::array<std::int32_t, 3>;

/// An indexed triangle mesh: plain data, no invariants enforced. validate() reports what is wrong
/// with one; read_mesh() and the generators return meshes whose indices are in range.
struct TriangleMesh {
  std::vector<Vec3> positions;     ///< Vertex positions, model units.
  std::vector<Triangle> triangles; ///< Indices into positions.

  std::int32_t num_vertices() const { return static_cast<std::int32_t>(positions.size()); }
  std::int32_t num_triangles() const { return static_cast<std::int32_t>(triangles.size()); }
};

} // namespace texsim::geom
