#pragma once
/// The part of a mesh made of chosen triangles, with the map back to the whole mesh's vertices:
/// what one rank owns after partitioning, and what it writes as its output piece.
#include "geom/triangle_mesh.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

struct Submesh {
  TriangleMesh mesh;                         ///< vertices renumbered 0..n-1 in first-use order
  std::vector<std::int32_t> global_vertex;   ///< local vertex -> vertex of the whole mesh
  std::vector<std::int32_t> global_triangle; ///< local triangle -> triangle of the whole mesh
};

/// The triangles t with triangle_part[t] == part, in increasing id order. Serial.
Submesh extract_part(const TriangleMesh& mesh, const std::vector<int>& triangle_part, int part);

/// The listed triangles of `mesh`, in the order given (ids in range). Serial.
Submesh extract_triangles(const TriangleMesh& mesh, std::span<const std::int32_t> triangles);

} // namespace texsim::geom
