#include "geom/surface_cells.hpp"

#include "core/error.hpp"
#include "geom/morton_order.hpp"
#include "geom/point_halo.hpp"
#include "par/allgather_runs.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

namespace texsim::geom {
namespace {

struct AreaRecord {
  std::int64_t cell;
  std::int32_t triangle;
  double area;
};

/// A piece of the border between `cell` and `other` inside `triangle`, as measured on the piece
/// of cell `from` (each border is measured from both sides; both measurements reach both owners).
struct BorderRecord {
  std::int64_t cell;
  std::int64_t other;
  std::int32_t triangle;
  std::int64_t from;
  double length;
};

std::int32_t owned_index(std::span<const std::int64_t> ids, std::int64_t id) {
  const auto it = std::lower_bound(ids.begin(), ids.end(), id);
  TEXSIM_VERIFY(it != ids.end() && *it == id, "cell " << id << " is not owned here");
  return std::int32_t(it - ids.begin());
}

std::vector<Vec3> positions_of(std::span<const SurfacePoint> points) {
  std::vector<Vec3> positions;
  positions.reserve(points.size());
  for (const auto& p : points)
    positions.push_back(p.position);
  return positions;
}

} // namespace

SurfaceCells::SurfaceCells(const par::Comm& comm, const DistributedTriangles& surface,
                           std::uint64_t seed, const SurfaceCellsSettings& settings)
    : global_count_(settings.count) {
  TEXSIM_VERIFY(settings.count > 0, "SurfaceCells needs at least one cell");
  surface_area_ = surface.total_area();
  spacing_ = std::sqrt(surface_area_ / double(settings.count));
  number_along_morton_curve(comm, surface.bounds(),
                            relaxed_surface_points(comm, surface, settings.count, seed,
                                                   settings.relaxation, &relaxation_));
  build_view(comm, surface, settings.halo_spacings * spacing_, settings.keep_pieces);
  reduce_pieces(comm, settings.keep_pieces);
  build_stencil(comm);
}

void SurfaceCells::number_along_morton_curve(const par::Comm& comm, const Box3& bounds,
                                             DistributedSurfacePoints relaxed) {
  // Cell ids follow the points sorted by (Morton key in the mesh's bounding box, point id); the
  // sort leaves rank r the even run of cells floor(cell p / n) = r, in id order.
  points_ = sort_along_morton_curve(comm, bounds, std::move(relaxed)).points;
  rank_offsets_ = par::run_offsets(comm, owned_count());
  owned_begin_ = rank_offsets_[comm.rank];
  ids_.resize(points_.size());
  std::iota(ids_.begin(), ids_.end(), owned_begin_);
}

void SurfaceCells::build_view(const par::Comm& comm, const DistributedTriangles& surface,
                              double halo, bool keep_polygons) {
  // This rank's share of the triangles, numbered in the whole mesh's order.
  const LocalSurface& share = surface.owned_surface();
  const TriangleMesh& mesh = share.mesh;
  std::vector<std::int32_t> local_triangles(share.triangle_ids.size());
  std::iota(local_triangles.begin(), local_triangles.end(), 0);
  for (const std::int64_t id : share.triangle_ids)
    triangles_.push_back(std::int32_t(id));
  // The halo: other ranks' cells within `halo` of this rank's triangles. Every point of a
  // triangle lies within its longest edge of a corner, so boxes around the corners grown by
  // halo + longest edge cover the triangles closely (one box per occupied grid cell).
  std::vector<Vec3> corners;
  double longest_edge = 0;
  for (const auto& tri : mesh.triangles)
    for (int c = 0; c < 3; ++c) {
      corners.push_back(mesh.positions[tri[c]]);
      longest_edge = std::max(longest_edge,
                              (mesh.positions[tri[c]] - mesh.positions[tri[(c + 1) % 3]]).norm());
    }
  const double reach = halo + longest_edge;
  const auto needed = covering_boxes(corners, 3.0 * reach, reach);
  const auto owned_positions = positions_of(points_);
  const auto halo_points = exchange_point_halo(comm, ids_, owned_positions, needed);

  for (std::int32_t i = 0; i < owned_count(); ++i) {
    view_ids_.push_back(ids_[i]);
    view_positions_.push_back(owned_positions[i]);
    view_blocks_.push_back(std::int32_t(owned_begin_ + i));
    view_owners_.push_back(comm.rank);
  }
  for (const auto& h : halo_points) {
    view_ids_.push_back(h.id);
    view_positions_.push_back(h.position);
    view_blocks_.push_back(std::int32_t(rank_offsets_[h.owner] + h.owner_index));
    view_owners_.push_back(h.owner);
  }
  pieces_ =
      restricted_voronoi_pieces(mesh, local_triangles, view_positions_, view_ids_, keep_polygons);
  for (auto& piece : pieces_)
    piece.triangle = triangles_[std::size_t(piece.triangle)];
}

void SurfaceCells::reduce_pieces(const par::Comm& comm, bool keep_pieces) {
  std::vector<std::vector<AreaRecord>> areas_out(comm.size);
  std::vector<std::vector<BorderRecord>> borders_out(comm.size);
  for (const auto& piece : pieces_) {
    const std::int64_t cell = view_ids_[piece.seed];
    areas_out[view_owners_[piece.seed]].push_back({cell, piece.triangle, piece.area});
    for (const auto& [other_seed, length] : piece.borders) {
      const std::int64_t other = view_ids_[other_seed];
      borders_out[view_owners_[piece.seed]].push_back({cell, other, piece.triangle, cell, length});
      borders_out[view_owners_[other_seed]].push_back({other, cell, piece.triangle, cell, length});
    }
  }
  if (!keep_pieces)
    pieces_ = {};
  auto areas_in = par::exchange_records(comm, std::move(areas_out));
  auto borders_in = par::exchange_records(comm, std::move(borders_out));

  // Sums in a fixed order (by triangle, then by the measuring cell) give the same bits on every
  // partition, and the same bits for (i, j) as for (j, i).
  std::sort(areas_in.begin(), areas_in.end(), [](const AreaRecord& a, const AreaRecord& b) {
    return std::tie(a.cell, a.triangle) < std::tie(b.cell, b.triangle);
  });
  areas_.assign(ids_.size(), 0.0);
  for (const auto& r : areas_in)
    areas_[owned_index(ids_, r.cell)] += r.area;

  std::sort(borders_in.begin(), borders_in.end(), [](const BorderRecord& a, const BorderRecord& b) {
    return std::tie(a.cell, a.other, a.triangle, a.from) <
           std::tie(b.cell, b.other, b.triangle, b.from);
  });
  borders_.assign(ids_.size(), {});
  for (const auto& r : borders_in) {
    auto& row = borders_[owned_index(ids_, r.cell)];
    if (row.empty() || row.back().first != r.other)
      row.emplace_back(r.other, 0.0);
    row.back().second += 0.5 * r.length;
  }
}

void SurfaceCells::build_stencil(const par::Comm& comm) {
  // Neighbours lie within a few spacings: the halo around the owned cells supplies the ghosts'
  // positions and block indices.
  const auto owned_positions = positions_of(points_);
  const double reach = 6.0 * spacing_;
  const auto nearby = exchange_point_halo(comm, ids_, owned_positions,
                                          covering_boxes(owned_positions, 3.0 * reach, reach));
  const auto find_nearby = [&](std::int64_t id) -> const HaloPoint& {
    const auto it = std::lower_bound(nearby.begin(), nearby.end(), id,
                                     [](const HaloPoint& h, std::int64_t v) { return h.id < v; });
    TEXSIM_VERIFY(it != nearby.end() && it->id == id,
                  "cell " << id << " borders an owned cell but is not within the halo");
    return *it;
  };

  std::vector<std::int64_t> ghost_ids;
  for (const auto& row : borders_)
    for (const auto& [other, length] : row)
      if (!std::binary_search(ids_.begin(), ids_.end(), other))
        ghost_ids.push_back(other);
  std::sort(ghost_ids.begin(), ghost_ids.end());
  ghost_ids.erase(std::unique(ghost_ids.begin(), ghost_ids.end()), ghost_ids.end());
  ghost_ids_ = ghost_ids;
  for (const std::int64_t id : ghost_ids_) {
    const HaloPoint& h = find_nearby(id);
    ghost_positions_.push_back(h.position);
    ghost_blocks_.push_back(std::int32_t(rank_offsets_[h.owner] + h.owner_index));
  }

  neighbors_.offsets.assign(1, 0);
  std::int64_t cut = 0;
  for (std::int32_t i = 0; i < owned_count(); ++i) {
    for (const auto& [other, length] : borders_[i]) {
      if (!(length > 0.0))
        continue;
      std::int32_t local;
      Vec3 position;
      const auto owned = std::lower_bound(ids_.begin(), ids_.end(), other);
      if (owned != ids_.end() && *owned == other) {
        local = std::int32_t(owned - ids_.begin());
        position = points_[local].position;
      } else {
        const auto slot = std::lower_bound(ghost_ids_.begin(), ghost_ids_.end(), other);
        local = owned_count() + std::int32_t(slot - ghost_ids_.begin());
        position = ghost_positions_[slot - ghost_ids_.begin()];
        ++cut;
      }
      neighbors_.indices.push_back(local);
      couplings_.push_back(length / (points_[i].position - position).norm());
    }
    neighbors_.offsets.push_back(std::int64_t(neighbors_.indices.size()));
  }
  borders_.clear();

  std::int64_t cut_sum = 0, owned_max = 0, ghosts_max = 0;
  const std::int64_t owned = owned_count(), ghosts = std::int64_t(ghost_ids_.size());
  MPI_Allreduce(&cut, &cut_sum, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  MPI_Allreduce(&owned, &owned_max, 1, MPI_INT64_T, MPI_MAX, comm.raw);
  MPI_Allreduce(&ghosts, &ghosts_max, 1, MPI_INT64_T, MPI_MAX, comm.raw);
  quality_.edge_cut = cut_sum / 2;
  quality_.imbalance = double(owned_max) * comm.size / double(global_count_);
  quality_.ghosts_max = ghosts_max;
}

} // namespace texsim::geom
