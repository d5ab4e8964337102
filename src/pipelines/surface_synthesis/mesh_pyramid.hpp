#pragma once
/// Wei-Levoy's mesh pyramid G_s (SIGGRAPH '01, Section 3.1; Table 3, lines 2-3): the surface
/// simplified level by level, each level retiled by Turk's method into evenly spread vertices, a
/// quarter as many on each coarser level. The finest level's vertex count sets the texture's scale
/// (Fig. 2).
#include "geom/distributed_triangles.hpp"
#include "geom/surface_cells.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// CounterRng stream from which each level's retiling seed is drawn, keyed by the level.
inline constexpr std::uint32_t kLevelSeedStream = 0x5310;

/// Simplified surfaces keep this many triangles per vertex of their level (see build_mesh_pyramid).
inline constexpr std::int64_t kTrianglesPerLevelVertex = 8;

struct MeshPyramidSettings {
  std::int64_t finest_count = 24576; ///< vertices of level 0 (`surface_synthesis.vertices`)
  int levels = 4;                    ///< `surface_synthesis.levels`
  /// Relaxation sweeps and halo of the retiling; `cells.count` is ignored (set per level).
  geom::SurfaceCellsSettings cells;
};

/// One retiled level split over the ranks: rank r holds the vertices of its run [rank_offsets[r],
/// rank_offsets[r + 1]) and a share of the triangles; no rank holds the whole level.
struct RetiledLevel {
  /// Positions of this rank's run: vertex rank_offsets[r] + i at i (vertex v = SurfaceCells id
  /// v, Morton order).
  std::vector<geom::Vec3> positions;
  /// Unit area-weighted vertex normals of the run (geom::vertex_normals' bits on the whole level).
  std::vector<geom::Vec3> normals;
  /// The level's triangles split over the ranks (windows of them are fetched where needed).
  geom::DistributedTriangles triangles;
  /// The triangles with a corner in this rank's run (run_star): the run's normals, 1-rings and
  /// frame pieces.
  geom::LocalSurface star;
  /// First owned id of each rank and the total at the end (ranks + 1 entries): SurfaceCells' runs
  /// (par/id_runs.hpp).
  std::vector<std::int64_t> rank_offsets;
  double spacing = 0; ///< d_L = sqrt(2 A_L), A_L the mean triangle area of the level (Section 3.3)
  /// fnv1a64 of the whole level's positions then triangles (the checkpoints' hierarchy hash).
  std::uint64_t mesh_hash = 0;

  std::int64_t vertex_count() const { return rank_offsets.back(); }
  std::int64_t triangle_count() const { return triangles.global_count(); }
  std::int64_t run_begin(int rank) const { return rank_offsets[std::size_t(rank)]; }
};

/// The level of `root_mesh`, held by rank 0 (the others pass an empty mesh), with runs
/// `rank_offsets` (every rank's): rank 0 hashes it, sends each rank its run's positions and
/// splits its triangles (geom::DistributedTriangles::from_root); each rank gets its run's star
/// (run_star) and computes its run's normals from it. Collective.
RetiledLevel distribute_level(const par::Comm& comm, const geom::TriangleMesh& root_mesh,
                              std::vector<std::int64_t> rank_offsets);

/// The positions of level vertices `ids` (sorted, distinct), fetched from their owners'
/// runs. Collective.
std::vector<geom::Vec3> fetch_level_positions(const par::Comm& comm, const RetiledLevel& level,
                                              std::span<const std::int64_t> ids);

/// The whole level's positions on rank 0, by id (the others get none). Collective.
std::vector<geom::Vec3> gather_level_positions(const par::Comm& comm, const RetiledLevel& level);

/// The whole level on rank 0 (the others get an empty mesh), for tests.
/// Collective.
geom::TriangleMesh gather_level_mesh(const par::Comm& comm, const RetiledLevel& level);

/// Levels [0] (finest_count vertices) to [levels - 1] (finest_count / 4^(levels - 1), rounded
/// down). Level k places its vertices with geom::SurfaceCells (relaxed, Morton-numbered; seed
/// drawn from CounterRng(seed, kLevelSeedStream) keyed by k) on level 0's input surface itself
/// and, for k > 0, on geom::simplify(surface, min(input triangles, kTrianglesPerLevelVertex *
/// count)): about 8 triangles per cell keep the simplified shape well within a cell spacing, and
/// the input is never refined. Every cell's centre is gathered by id and the level's mesh is
/// geom::restricted_delaunay of them on the surface they were placed on.
///
/// Throws InputError (naming surface_synthesis.levels and surface_synthesis.vertices) when
/// settings.levels < 1, the coarsest level would get fewer than 12 vertices, or a level's mesh is
/// not a consistently oriented manifold using every vertex with the input's Euler characteristic
/// and boundary: the message gives the level, its vertex count and what was found. The levels are
/// the same for any rank or thread count (SurfaceCells ids do not depend on them).
/// Collective over comm. Only rank 0's `surface` is read (the others may pass an empty mesh): rank
/// 0 simplifies it, splits each level's surface over the ranks for the retiling
/// (geom::DistributedTriangles::from_root) and connects the cells (every rank cuts the Voronoi
/// pieces of a run of the surface's triangles: geom::restricted_delaunay's collective form), so no
/// other rank holds it. Rank 0 checks each connected level and distributes it
/// (distribute_level).
std::vector<RetiledLevel> build_mesh_pyramid(const par::Comm& comm,
                                             const geom::TriangleMesh& surface, std::uint64_t seed,
                                             const MeshPyramidSettings& settings);

} // namespace texsim::pipelines::surface_synthesis
