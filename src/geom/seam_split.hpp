#pragma once
/// A mesh with one texture coordinate per vertex, as renderers and file formats want it: vertices
/// are duplicated along the seams of an atlas, where a vertex has different uv in different
/// triangles.
#include "geom/triangle_mesh.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace texsim::geom {

struct SeamSplitMesh {
  TriangleMesh mesh;                         ///< same triangles, vertices split at seams
  std::vector<Eigen::Vector2d> uv;           ///< one per vertex of mesh
  std::vector<std::int32_t> original_vertex; ///< the input vertex each vertex copies
};

/// Splits `mesh` wherever the corners of one vertex carry different uv (exact comparison) in
/// `corner_uv` (one array per triangle, as geom::TextureAtlas gives). New vertices are numbered in
/// order of first use by the triangles' corners (triangle by triangle), so the result depends
/// only on the input. Serial.
SeamSplitMesh split_at_seams(const TriangleMesh& mesh,
                             const std::vector<std::array<Eigen::Vector2d, 3>>& corner_uv);

} // namespace texsim::geom
