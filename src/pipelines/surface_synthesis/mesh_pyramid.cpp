#include "pipelines/surface_synthesis/mesh_pyramid.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/rng.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_simplification.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/mesh_validation.hpp"
#include "geom/restricted_delaunay.hpp"
#include "par/allgather_runs.hpp"
#include "par/collective.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Fewer vertices than an icosahedron cannot retile a closed surface into a useful level.
constexpr std::int64_t kMinLevelVertices = 12;

std::uint64_t level_seed(std::uint64_t seed, int level) {
  const auto bits = CounterRng(seed, kLevelSeedStream).bits(std::uint64_t(level), 0);
  return (std::uint64_t{bits[0]} << 32) | bits[1];
}

/// Every cell's centre, indexed by id, on every rank.
std::vector<geom::Vec3> gather_cell_positions(const par::Comm& comm,
                                              const geom::SurfaceCells& cells) {
  std::vector<geom::Vec3> positions(std::size_t(cells.global_count()));
  for (std::int32_t i = 0; i < cells.owned_count(); ++i) {
    TEXSIM_VERIFY(cells.ids()[std::size_t(i)] == cells.owned_begin() + i,
                  "mesh pyramid: owned cell ids are not a contiguous run");
    positions[std::size_t(cells.owned_begin() + i)] = cells.points()[std::size_t(i)].position;
  }
  static_assert(sizeof(geom::Vec3) == 3 * sizeof(double));
  par::allgather_runs(comm, cells.rank_offsets(), positions.data(), 3, MPI_DOUBLE);
  return positions;
}

/// What a retiling must share with the input surface: kept instead of the input's whole
/// MeshTopology, which would stay on rank 0 through every level.
struct SurfaceShape {
  std::size_t boundary_edges = 0;
  bool closed = false;
  std::int64_t euler_characteristic = 0;

  SurfaceShape() = default;
  explicit SurfaceShape(const geom::MeshTopology& topology)
      : boundary_edges(topology.boundary_edges().size()), closed(topology.is_closed()),
        euler_characteristic(topology.euler_characteristic()) {}
};

/// What keeps `mesh` from being a retiling of a surface of `input`'s shape, in words; empty when
/// nothing does.
std::string topology_defects(const geom::TriangleMesh& mesh, const SurfaceShape& input) {
  const geom::MeshTopology topology(mesh);
  std::string defects;
  const auto add = [&](const std::string& what) {
    defects += (defects.empty() ? "" : ", ") + what;
  };
  if (!topology.non_manifold_edges().empty())
    add(log::cat(topology.non_manifold_edges().size(), " non-manifold edges"));
  if (!topology.non_manifold_vertices().empty())
    add(log::cat(topology.non_manifold_vertices().size(), " non-manifold vertices"));
  if (!topology.isolated_vertices().empty())
    add(log::cat(topology.isolated_vertices().size(), " vertices in no triangle"));
  if (topology.boundary_edges().size() != input.boundary_edges &&
      (topology.is_closed() || input.closed))
    add(log::cat(topology.boundary_edges().size(), " boundary edges (the surface has ",
                 input.boundary_edges, ")"));
  if (topology.euler_characteristic() != input.euler_characteristic)
    add(log::cat("Euler characteristic ", topology.euler_characteristic(), " (the surface's is ",
                 input.euler_characteristic, ")"));
  if (defects.empty()) {
    const auto orientation = geom::validate(mesh).inconsistent_orientation;
    if (orientation)
      add(log::cat(orientation.count, " edges with inconsistently oriented triangles"));
  }
  return defects;
}

/// Level `level` retiled on rank 0's `surface` (`surface_shape` its shape, rank 0's).
RetiledLevel retile_level(const par::Comm& comm, const geom::TriangleMesh& surface,
                          const SurfaceShape& surface_shape, std::uint64_t seed,
                          const MeshPyramidSettings& settings, int level) {
  const std::int64_t count = settings.finest_count >> (2 * level);
  // Level 0 on the surface itself; coarser levels on a simplification with a few triangles per
  // cell, never more than the input has. Rank 0 alone holds the surface and simplifies it.
  geom::TriangleMesh simplified;
  const geom::TriangleMesh* placed_on = &surface;
  par::run_collectively(comm, [&] {
    const std::int64_t target = kTrianglesPerLevelVertex * count;
    if (comm.is_root() && level > 0 && target < surface.num_triangles()) {
      simplified = geom::simplify(surface, std::size_t(target));
      placed_on = &simplified;
    }
  });
  RetiledLevel retiled;
  {
    // Only the cells' centres and runs outlive the retiling (not their Voronoi pieces).
    geom::SurfaceCellsSettings cells_settings = settings.cells;
    cells_settings.count = count;
    cells_settings.keep_pieces = false;
    const geom::SurfaceCells cells(comm, geom::DistributedTriangles::from_root(comm, *placed_on),
                                   level_seed(seed, level), cells_settings);
    retiled.mesh.positions = gather_cell_positions(comm, cells);
    const auto offsets = cells.rank_offsets();
    retiled.rank_offsets.assign(offsets.begin(), offsets.end());
  }
  // Every rank cuts the Voronoi pieces of a share of the surface rank 0 holds; rank 0 connects
  // the cells and checks the result; every rank gets its triangles.
  std::vector<std::int64_t> ids(retiled.mesh.positions.size());
  std::iota(ids.begin(), ids.end(), std::int64_t{0});
  geom::TriangleMesh connected =
      geom::restricted_delaunay(comm, *placed_on, retiled.mesh.positions, ids);
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    retiled.mesh = std::move(connected);
    const std::string defects = topology_defects(retiled.mesh, surface_shape);
    if (!defects.empty())
      TEXSIM_INPUT_ERROR("surface_synthesis.vertices, surface_synthesis.levels: level "
                         << level << " of " << settings.levels << " (" << count
                         << " vertices) does not retile the surface into a manifold like it: "
                         << defects
                         << "; its vertices are too few for the surface's thin parts: use more "
                            "surface_synthesis.vertices or fewer surface_synthesis.levels");
  });
  par::broadcast_records(comm, retiled.mesh.triangles);
  const std::int64_t first = retiled.rank_offsets[std::size_t(comm.rank)];
  retiled.normals = geom::vertex_normals(retiled.mesh, first,
                                         retiled.rank_offsets[std::size_t(comm.rank) + 1] - first);
  retiled.spacing =
      std::sqrt(2.0 * geom::total_area(retiled.mesh) / double(retiled.mesh.num_triangles()));
  log::info(log::cat("mesh pyramid: level ", level, ": ", count, " vertices, ",
                     retiled.mesh.num_triangles(), " triangles, spacing ", retiled.spacing,
                     " (placed on ", placed_on->num_triangles(), " triangles)"));
  return retiled;
}

} // namespace

std::vector<RetiledLevel> build_mesh_pyramid(const par::Comm& comm,
                                             const geom::TriangleMesh& surface, std::uint64_t seed,
                                             const MeshPyramidSettings& settings) {
  if (settings.levels < 1)
    TEXSIM_INPUT_ERROR("surface_synthesis.levels: " << settings.levels
                                                    << " levels; at least 1 is needed");
  // A quarter as many vertices per coarser level (levels past 31 would leave none).
  const std::int64_t coarsest =
      settings.levels > 31 ? 0 : settings.finest_count >> (2 * (settings.levels - 1));
  if (coarsest < kMinLevelVertices)
    TEXSIM_INPUT_ERROR("surface_synthesis.levels, surface_synthesis.vertices: "
                       << settings.levels << " levels of " << settings.finest_count
                       << " vertices leave " << coarsest
                       << " on the coarsest level (a quarter per level), fewer than "
                       << kMinLevelVertices << "; use fewer levels or more vertices");
  const SurfaceShape surface_shape =
      comm.is_root() ? SurfaceShape(geom::MeshTopology(surface)) : SurfaceShape();
  std::vector<RetiledLevel> pyramid;
  for (int level = 0; level < settings.levels; ++level)
    pyramid.push_back(retile_level(comm, surface, surface_shape, seed, settings, level));
  return pyramid;
}

} // namespace texsim::pipelines::surface_synthesis
