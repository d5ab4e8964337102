#pragma once
/// Wei-Levoy's mesh pyramid G_s (Section 3.1, Table 3 lines 2-3): the surface simplified level by
/// level and each level retiled by Turk's method into evenly spread vertices, a quarter as many on
/// each coarser level. The finest level's vertex count sets the texture's scale (Fig. 2).
#include "geom/surface_cells.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

struct MeshPyramidSettings {
  std::int64_t finest_count = 24576; ///< vertices of level 0
  int levels = 4;
  geom::SurfaceCellsSettings cells; ///< relaxation of the retiling (its count is set per level)
};

/// One retiled level, replicated on every rank (for now).
struct RetiledLevel {
  geom::TriangleMesh mesh;         ///< vertex v = SurfaceCells id v (Morton order)
  std::vector<geom::Vec3> normals; ///< unit area-weighted vertex normals of `mesh`
  /// First owned id of each rank and the total at the end (ranks + 1 entries): SurfaceCells' runs.
  std::vector<std::int64_t> rank_offsets;
  double spacing = 0; ///< d_L = sqrt(2 A_L), A_L the mean triangle area (Wei-Levoy 3.3)
};

/// Levels [0] finest (finest_count vertices) to [levels - 1] (finest_count / 4^(levels-1)).
/// Level k places its vertices on geom::simplify(surface) with at most 8 times as many triangles
/// as it gets vertices (level 0 on the surface itself), retiles them with geom::SurfaceCells
/// (seed keyed by level) and triangulates them by geom::restricted_delaunay. Throws InputError
/// naming surface_synthesis.levels / .vertices when a level has fewer than 12 vertices or its mesh
/// is not a manifold with the surface's Euler characteristic. Same bytes on any rank count.
/// Collective.
std::vector<RetiledLevel> build_mesh_pyramid(const par::Comm& comm,
                                             const geom::TriangleMesh& surface, std::uint64_t seed,
                                             const MeshPyramidSettings& settings);

} // namespace texsim::pipelines::surface_synthesis
