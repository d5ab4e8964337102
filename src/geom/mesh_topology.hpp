#pragma once
/// Adjacency of a triangle mesh, built once, laid out for FEM assembly and neighbourhood walks.
#include "geom/triangle_mesh.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::geom {

/// Compressed sparse rows: row i is indices[offsets[i] .. offsets[i+1]).
struct CsrAdjacency {
  std::vector<std::int64_t> offsets; ///< size rows + 1, offsets[0] == 0
  std::vector<std::int32_t> indices;

  std::int32_t rows() const { return static_cast<std::int32_t>(offsets.size()) - 1; }
  std::span<const std::int32_t> row(std::int32_t i) const {
    return {indices.data() + offsets[i], indices.data() + offsets[i + 1]};
  }
};

/// An undirected edge as its two vertex ids, smaller first.
using Edge = std::array<std::int32_t, 2>;

/// Edges, incidences and manifoldness of a mesh. The mesh's indices must be in range (validate()
/// checks that); any other defect (non-manifold edges, boundaries, isolated vertices) is allowed
/// and reported. Edge ids follow the lexicographic order of their sorted vertex pairs, so they do
/// not depend on triangle order. Serial, not collective.
class MeshTopology {
public:
  explicit MeshTopology(const TriangleMesh& mesh);

  std::int32_t num_vertices() const { return vertex_triangles_.rows(); }
  std::int32_t num_edges() const { return static_cast<std::int32_t>(edges_.size()); }
  std::int32_t num_triangles() const { return static_cast<std::int32_t>(triangle_edges_.size()); }

  /// All unique edges, sorted lexicographically.
  const std::vector<Edge>& edges() const { return edges_; }
  /// Triangles containing edge e, in increasing order: one on a boundary, two inside a manifold,
  /// more on a non-manifold edge.
  std::span<const std::int32_t> edge_triangles(std::int32_t e) const {
    return edge_triangles_.row(e);
  }
  /// Edge ids of triangle t; entry i is the edge opposite corner i (joining corners i+1 and i+2).
  const std::array<std::int32_t, 3>& triangle_edges(std::int32_t t) const {
    return triangle_edges_[t];
  }
  /// Id of the edge joining a and b (either order), or -1 when there is none.
  std::int32_t find_edge(std::int32_t a, std::int32_t b) const;

  /// Vertex -> incident triangles (increasing ids), CSR.
  const CsrAdjacency& vertex_triangles() const { return vertex_triangles_; }
  /// Vertex -> neighbour vertices joined by an edge (sorted ids), CSR.
  const CsrAdjacency& vertex_neighbors() const { return vertex_neighbors_; }

  /// Edges with exactly one triangle, increasing ids.
  const std::vector<std::int32_t>& boundary_edges() const { return boundary_edges_; }
  /// Vertices on a boundary edge, sorted.
  const std::vector<std::int32_t>& boundary_vertices() const { return boundary_vertices_; }
  /// Edges with more than two triangles, increasing ids.
  const std::vector<std::int32_t>& non_manifold_edges() const { return non_manifold_edges_; }
  /// Vertices whose incident triangles form more than one fan (edge-connected around the vertex),
  /// e.g. the tip shared by two cones; sorted. Vertices without triangles are not listed.
  const std::vector<std::int32_t>& non_manifold_vertices() const { return non_manifold_vertices_; }
  /// Vertices used by no triangle, sorted.
  const std::vector<std::int32_t>& isolated_vertices() const { return isolated_vertices_; }

  /// V - E + F, counting every vertex of the mesh (2 for a sphere, 0 for a torus).
  std::int64_t euler_characteristic() const {
    return std::int64_t{num_vertices()} - num_edges() + num_triangles();
  }
  /// No boundary edges.
  bool is_closed() const { return boundary_edges_.empty(); }
  /// Every edge has one or two triangles and every vertex a single fan.
  bool is_manifold() const { return non_manifold_edges_.empty() && non_manifold_vertices_.empty(); }

private:
  std::vector<Edge> edges_;
  CsrAdjacency edge_triangles_;
  std::vector<std::array<std::int32_t, 3>> triangle_edges_;
  CsrAdjacency vertex_triangles_;
  CsrAdjacency vertex_neighbors_;
  std::vector<std::int32_t> boundary_edges_;
  std::vector<std::int32_t> boundary_vertices_;
  std::vector<std::int32_t> non_manifold_edges_;
  std::vector<std::int32_t> non_manifold_vertices_;
  std::vector<std::int32_t> isolated_vertices_;
};

} // namespace texsim::geom
