#pragma once
/// One frame's fluid surface with what building and projecting patches need: adjacency, a
/// closest-point tree, triangle normals and the mean edge length.
#include "geom/aabb_tree.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"

#include <vector>

namespace texsim::pipelines::fluid_lapped {

struct FrameSurface {
  /// Throws texsim::Error when the mesh has no triangles.
  explicit FrameSurface(geom::TriangleMesh surface);

  geom::TriangleMesh mesh;
  geom::MeshTopology topology;
  geom::AabbTree tree;
  std::vector<geom::Vec3> triangle_normals; ///< unit normals (zero for degenerate triangles)
  double mean_edge_length = 0;
};

} // namespace texsim::pipelines::fluid_lapped
