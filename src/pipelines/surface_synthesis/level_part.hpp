#pragma once
/// A rank's part of a retiled level: the triangles near its own vertices, with their topology, so
/// no rank builds the topology of a whole level. Patches flattened on the part are the patches
/// the whole level gives as long as they use only complete triangles (every triangle sharing a
/// corner with them is in the part); the stencils check that for every patch.
#include "geom/distributed_triangles.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/submesh.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

class LevelPart {
public:
  /// The triangles of `level` (split over the ranks) with a corner within `reach` of one of
  /// `centres` (inside geom::covering_boxes with cells of edge `reach`, so somewhat more), in
  /// increasing id order, taken from a window of the level around those boxes
  /// (DistributedTriangles::window), which holds every such triangle: the part is the one the
  /// whole level gives. Local vertex ids follow the vertices' ids on the level, so every order
  /// (triangles around a vertex or an edge, edge ids) is the level's. reach > 0. Collective.
  LevelPart(const par::Comm& comm, const geom::DistributedTriangles& level,
            std::span<const geom::Vec3> centres, double reach);

  const geom::TriangleMesh& mesh() const { return part_.mesh; }
  const geom::MeshTopology& topology() const { return topology_; }
  std::int32_t global_vertex(std::int32_t local) const {
    return part_.global_vertex[std::size_t(local)];
  }
  /// The local id of a vertex or triangle of the level, -1 when the part does not hold it.
  std::int32_t local_vertex(std::int32_t global) const;
  std::int32_t local_triangle(std::int32_t global) const;
  /// Whether every triangle of the level sharing a corner with local triangle t is in the part.
  bool complete(std::int32_t t) const { return complete_[std::size_t(t)] != 0; }

private:
  struct Selection;
  explicit LevelPart(Selection&& selection);

  geom::Submesh part_; ///< local vertices in increasing order of their ids on the level
  geom::MeshTopology topology_;
  std::vector<char> complete_;
};

/// How far from its centres a part reaches to hold the patches of radius `patch_radius` (which
/// includes about one triangle beyond the template): twice the radius. A patch triangle comes
/// within the radius of the origin in the flattened plane, and flattening keeps edge lengths, so
/// its corners are farther in space only where the surface bends strongly within one patch or
/// near a long edge. Whoever flattens on a part checks that each patch used complete triangles
/// only and flattens the few others again on a wider part (build_level_stencils).
double patch_reach(double patch_radius);

} // namespace texsim::pipelines::surface_synthesis
