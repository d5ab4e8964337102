#include "pipelines/surface_synthesis/mesh_pyramid.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/log.hpp"
#include "core/rng.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_simplification.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/mesh_validation.hpp"
#include "geom/restricted_delaunay.hpp"
#include "par/collective.hpp"
#include "par/fetch_from_owners.hpp"
#include "par/gather_to_root.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"
#include "pipelines/surface_synthesis/run_star.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Fewer vertices than an icosahedron cannot retile a closed surface into a useful level.
constexpr std::int64_t kMinLevelVertices = 12;

/// Positions as plain triples, which travel between ranks as bytes (Eigen's Vec3 is not
/// trivially copyable), and back.
using Xyz = std::array<double, 3>;

std::vector<Xyz> as_xyz(std::span<const geom::Vec3> positions) {
  std::vector<Xyz> xyz;
  xyz.reserve(positions.size());
  for (const geom::Vec3& p : positions)
    xyz.push_back({p.x(), p.y(), p.z()});
  return xyz;
}

std::vector<geom::Vec3> as_positions(const std::vector<Xyz>& xyz) {
  std::vector<geom::Vec3> positions;
  positions.reserve(xyz.size());
  for (const Xyz& p : xyz)
    positions.emplace_back(p[0], p[1], p[2]);
  return positions;
}

std::uint64_t level_seed(std::uint64_t seed, int level) {
  const auto bits = CounterRng(seed, kLevelSeedStream).bits(std::uint64_t(level), 0);
  return (std::uint64_t{bits[0]} << 32) | bits[1];
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
    const auto orientation = geom::inconsistent_orientation(mesh, topology);
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
  std::vector<std::int64_t> rank_offsets;
  geom::TriangleMesh connected;
  {
    std::vector<geom::Vec3> centres;
    std::vector<std::int64_t> ids;
    double halo = 0.0;
    {
      // Only the cells' runs and centres outlive the retiling (not their Voronoi pieces).
      geom::SurfaceCellsSettings cells_settings = settings.cells;
      cells_settings.count = count;
      cells_settings.keep_pieces = false;
      const geom::SurfaceCells cells(comm, geom::DistributedTriangles::from_root(comm, *placed_on),
                                     level_seed(seed, level), cells_settings);
      const auto offsets = cells.rank_offsets();
      rank_offsets.assign(offsets.begin(), offsets.end());
      for (const auto& point : cells.points())
        centres.push_back(point.position);
      ids.assign(cells.ids().begin(), cells.ids().end());
      halo = cells_settings.halo_spacings * cells.spacing();
    }
    // Every rank cuts the Voronoi pieces of a run of the surface rank 0 holds, against its cells'
    // centres and the other ranks' within the cells' own halo; rank 0 connects the cells.
    connected = geom::restricted_delaunay(comm, *placed_on, centres, ids, halo);
  }
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    const std::string defects = topology_defects(connected, surface_shape);
    if (!defects.empty())
      TEXSIM_INPUT_ERROR("surface_synthesis.vertices, surface_synthesis.levels: level "
                         << level << " of " << settings.levels << " (" << count
                         << " vertices) does not retile the surface into a manifold like it: "
                         << defects
                         << "; its vertices are too few for the surface's thin parts: use more "
                            "surface_synthesis.vertices or fewer surface_synthesis.levels");
  });
  RetiledLevel retiled = distribute_level(comm, connected, std::move(rank_offsets));
  log::info(log::cat("mesh pyramid: level ", level, ": ", count, " vertices, ",
                     retiled.triangle_count(), " triangles, spacing ", retiled.spacing,
                     " (placed on ", placed_on->num_triangles(), " triangles)"));
  return retiled;
}

} // namespace

RetiledLevel distribute_level(const par::Comm& comm, const geom::TriangleMesh& root_mesh,
                              std::vector<std::int64_t> rank_offsets) {
  RetiledLevel level;
  level.rank_offsets = std::move(rank_offsets);
  TEXSIM_VERIFY(std::int64_t(level.rank_offsets.size()) == comm.size + 1,
                "distribute_level: " << level.rank_offsets.size() << " run offsets for "
                                     << comm.size << " ranks");
  if (comm.is_root()) {
    TEXSIM_VERIFY(std::int64_t(root_mesh.positions.size()) == level.vertex_count(),
                  "distribute_level: " << root_mesh.positions.size() << " vertices for runs of "
                                       << level.vertex_count());
    // fnv1a64 of the positions' bytes then the triangles', without copying them.
    level.mesh_hash = fnv1a64({reinterpret_cast<const char*>(root_mesh.triangles.data()),
                               root_mesh.triangles.size() * sizeof(geom::Triangle)},
                              fnv1a64({reinterpret_cast<const char*>(root_mesh.positions.data()),
                                       root_mesh.positions.size() * sizeof(geom::Vec3)}));
  }
  MPI_Bcast(&level.mesh_hash, 1, MPI_UINT64_T, 0, comm.raw);
  level.positions = as_positions(par::scatter_from_root<Xyz>(comm, [&](int rank) {
    return as_xyz(std::span(root_mesh.positions)
                      .subspan(std::size_t(level.run_begin(rank)),
                               std::size_t(level.run_begin(rank + 1) - level.run_begin(rank))));
  }));
  level.triangles = geom::DistributedTriangles::from_root(
      comm, root_mesh, {}, geom::DistributedTriangles::Sampling::none);
  // DistributedTriangles' total area is total_area()'s bits on the whole mesh.
  level.spacing = std::sqrt(2.0 * level.triangles.total_area() / double(level.triangle_count()));
  level.star = run_star(comm, level);
  const auto count = std::int64_t(level.positions.size());
  level.normals = geom::vertex_normals(
      level.star.mesh, star_run_begin(level.star, level.run_begin(comm.rank), count), count);
  return level;
}

std::vector<geom::Vec3> fetch_level_positions(const par::Comm& comm, const RetiledLevel& level,
                                              std::span<const std::int64_t> ids) {
  const auto run = as_xyz(level.positions);
  return as_positions(
      par::fetch_from_owners(comm, level.rank_offsets, ids, std::span<const Xyz>(run)));
}

std::vector<geom::Vec3> gather_level_positions(const par::Comm& comm, const RetiledLevel& level) {
  const auto run = as_xyz(level.positions);
  return as_positions(par::gather_to_root(comm, std::span<const Xyz>(run)));
}

geom::TriangleMesh gather_level_mesh(const par::Comm& comm, const RetiledLevel& level) {
  geom::TriangleMesh mesh;
  mesh.positions = gather_level_positions(comm, level);
  // Each triangle as its id and corner ids (the positions come by vertex, above).
  const geom::LocalSurface& own = level.triangles.owned_surface();
  std::vector<std::array<std::int64_t, 4>> share;
  for (std::size_t k = 0; k < own.triangle_ids.size(); ++k) {
    const geom::Triangle& c = own.mesh.triangles[k];
    share.push_back({own.triangle_ids[k], own.vertex_ids[std::size_t(c[0])],
                     own.vertex_ids[std::size_t(c[1])], own.vertex_ids[std::size_t(c[2])]});
  }
  auto triangles = par::gather_to_root(comm, std::span<const std::array<std::int64_t, 4>>(share));
  std::sort(triangles.begin(), triangles.end()); // by id
  for (const auto& t : triangles)
    mesh.triangles.push_back({std::int32_t(t[1]), std::int32_t(t[2]), std::int32_t(t[3])});
  return mesh;
}

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
