#include "pipelines/surface_synthesis/mesh_pyramid.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_simplification.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/restricted_delaunay.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Triangles of the surface a level's points are placed on, per point: enough that the simplified
/// surface follows the shape well below the level's vertex spacing.
constexpr std::int64_t kTrianglesPerVertex = 8;

/// Every cell's centre by id, on every rank.
std::vector<geom::Vec3> gather_positions(const par::Comm& comm, const geom::SurfaceCells& cells) {
  std::vector<double> owned;
  for (const auto& p : cells.points())
    owned.insert(owned.end(), {p.position.x(), p.position.y(), p.position.z()});
  const auto offsets = cells.rank_offsets();
  std::vector<int> counts(std::size_t(comm.size)), displs(std::size_t(comm.size));
  for (int r = 0; r < comm.size; ++r) {
    displs[std::size_t(r)] = int(3 * offsets[std::size_t(r)]);
    counts[std::size_t(r)] = int(3 * (offsets[std::size_t(r) + 1] - offsets[std::size_t(r)]));
  }
  std::vector<double> all(std::size_t(3 * cells.global_count()));
  MPI_Allgatherv(owned.data(), int(owned.size()), MPI_DOUBLE, all.data(), counts.data(),
                 displs.data(), MPI_DOUBLE, comm.raw);
  std::vector<geom::Vec3> positions;
  for (std::size_t i = 0; i < all.size(); i += 3)
    positions.emplace_back(all[i], all[i + 1], all[i + 2]);
  return positions;
}

} // namespace

std::vector<RetiledLevel> build_mesh_pyramid(const par::Comm& comm,
                                             const geom::TriangleMesh& surface, std::uint64_t seed,
                                             const MeshPyramidSettings& settings) {
  const geom::MeshTopology surface_topology(surface);
  const std::int64_t euler = surface_topology.euler_characteristic();
  std::vector<RetiledLevel> pyramid;
  for (int k = 0; k < settings.levels; ++k) {
    const std::int64_t count = settings.finest_count >> (2 * k);
    if (count < 12)
      throw InputError(log::cat("surface_synthesis.levels: level ", k, " of ", settings.levels,
                                " would have ", count, " vertices (", settings.finest_count,
                                " / 4^", k,
                                "); use fewer levels or more surface_synthesis."
                                "vertices"));
    const auto target =
        std::size_t(std::min<std::int64_t>(kTrianglesPerVertex * count, surface.num_triangles()));
    const geom::TriangleMesh placed_on = k == 0 ? surface : geom::simplify(surface, target);
    auto cells_settings = settings.cells;
    cells_settings.count = count;
    const std::uint64_t level_seed = seed + 0x9E3779B97F4A7C15ull * std::uint64_t(k);
    const geom::SurfaceCells cells(comm, placed_on, geom::MeshTopology(placed_on), level_seed,
                                   cells_settings);
    const auto positions = gather_positions(comm, cells);
    std::vector<std::int64_t> ids(positions.size());
    std::iota(ids.begin(), ids.end(), 0);

    RetiledLevel level;
    level.mesh = geom::restricted_delaunay(placed_on, positions, ids);
    const geom::MeshTopology topology(level.mesh);
    if (!topology.is_manifold() || topology.is_closed() != surface_topology.is_closed() ||
        topology.euler_characteristic() != euler || !topology.isolated_vertices().empty())
      throw InputError(log::cat(
          "surface_synthesis.vertices: the retiled mesh of level ", k, " (", count,
          " vertices) is not a manifold with the surface's Euler characteristic ", euler, " (got ",
          topology.euler_characteristic(), ", ", topology.non_manifold_edges().size(),
          " non-manifold edges, ", topology.isolated_vertices().size(),
          " vertices without triangles): too few vertices for the surface's thin parts; use more "
          "vertices or fewer surface_synthesis.levels"));
    level.normals = geom::vertex_normals(level.mesh);
    const auto offsets = cells.rank_offsets();
    level.rank_offsets.assign(offsets.begin(), offsets.end());
    const auto areas = geom::triangle_areas(level.mesh);
    const double mean_area =
        std::accumulate(areas.begin(), areas.end(), 0.0) / double(areas.size());
    level.spacing = std::sqrt(2 * mean_area);
    pyramid.push_back(std::move(level));
  }
  return pyramid;
}

} // namespace texsim::pipelines::surface_synthesis
