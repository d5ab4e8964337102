#include "pipelines/turk_rd/pattern_frames.hpp"

#include "geom/bump_map.hpp"
#include "geom/point_halo.hpp"
#include "io/parallel_surface_writer.hpp"
#include "par/global_range.hpp"

#include <mpi.h>

#include <algorithm>

namespace texsim::pipelines::turk_rd {
namespace {

std::unique_ptr<io::PvdSeries> open_series(const par::Comm& comm, const std::filesystem::path& path,
                                           std::optional<double> restart_time) {
  if (restart_time)
    return std::make_unique<io::PvdSeries>(io::PvdSeries::resume(comm, path, *restart_time));
  return std::make_unique<io::PvdSeries>(comm, path);
}

} // namespace

PatternFrames::PatternFrames(const par::Comm& comm, const geom::DistributedTriangles& input,
                             const geom::SurfaceCells& cells, const RenderSettings& render,
                             const std::filesystem::path& output_dir,
                             std::optional<double> restart_time)
    : comm_(comm), cells_(cells), render_(render), output_dir_(output_dir),
      piece_(std::make_unique<RenderPiece>(
          make_render_piece(comm, input, render.subdivision_levels))) {
  // Cells within the weighting radius of this piece, fetched from their owners every frame.
  const double radius = render.radius_spacings * cells.spacing();
  std::vector<geom::Vec3> owned_positions;
  for (const auto& p : cells.points())
    owned_positions.push_back(p.position);
  // The targets are the piece's vertices: boxes around them grown by the radius (and two
  // spacings, for the nearest-cell fallback) hold every cell a target can use.
  const double reach = radius + 2.0 * cells.spacing();
  const auto needed = geom::covering_boxes(piece_->mesh.positions, 3.0 * reach, reach);
  const auto nearby = geom::exchange_point_halo(comm, cells.ids(), owned_positions, needed);
  std::vector<geom::Vec3> sample_positions = owned_positions;
  std::vector<std::int64_t> sample_ids(cells.ids().begin(), cells.ids().end());
  std::vector<std::int32_t> ghost_blocks;
  for (const auto& h : nearby) {
    sample_positions.push_back(h.position);
    sample_ids.push_back(h.id);
    ghost_blocks.push_back(std::int32_t(cells.rank_offsets()[h.owner] + h.owner_index));
  }
  near_surface_ = std::make_unique<par::GhostedVector>(comm, cells.owned_count(), ghost_blocks);
  sampler_ = std::make_unique<PatternSampler>(piece_->mesh.positions, sample_positions, sample_ids,
                                              radius);
  near_pieces_ = std::make_unique<par::GhostedVector>(
      comm, cells.owned_count(), cells.view_blocks().subspan(std::size_t(cells.owned_count())));

  surface_series_ = open_series(comm, output_dir / "turk_rd_surface.pvd", restart_time);
  cells_series_ = open_series(comm, output_dir / "turk_rd_cells.pvd", restart_time);
  if (render.bump_scale > 0)
    bump_series_ = open_series(comm, output_dir / "turk_rd_bump.pvd", restart_time);
}

PatternFrames::~PatternFrames() = default;

std::vector<std::filesystem::path> PatternFrames::series() const {
  std::vector<std::filesystem::path> paths{output_dir_ / "turk_rd_surface.pvd",
                                           output_dir_ / "turk_rd_cells.pvd"};
  if (bump_series_)
    paths.push_back(output_dir_ / "turk_rd_bump.pvd");
  return paths;
}

void PatternFrames::write(std::int64_t step, const FrameData& data) {
  double lo = 0, hi = 1;
  if (render_.range) {
    lo = (*render_.range)[0];
    hi = (*render_.range)[1];
  } else {
    const auto range = par::global_range(comm_, data.shown);
    lo = range.min;
    hi = range.max;
    if (!(hi > lo))
      hi = lo + 1.0;
  }
  near_surface_->set_owned(data.shown);
  std::vector<double> pattern(piece_->mesh.positions.size());
  sampler_->sample(near_surface_->local(), pattern);
  write_surface(io::step_name(step), data.time, pattern, lo, hi);
  write_cells(io::step_name(step), data.time, data);
}

void PatternFrames::write_surface(const std::string& name, double time,
                                  std::span<const double> pattern, double lo, double hi) {
  const auto& piece = *piece_;
  const std::size_t n = piece.written_vertices.size();
  std::vector<double> xyz(3 * n), values(n), rgb(3 * n);
  for (std::size_t p = 0; p < n; ++p) {
    const std::int32_t v = piece.written_vertices[p];
    for (int axis = 0; axis < 3; ++axis)
      xyz[3 * p + axis] = piece.mesh.positions[v][axis];
    values[p] = pattern[v];
    const auto color = render_.colormap.color(pattern[v], lo, hi);
    for (int c = 0; c < 3; ++c)
      rgb[3 * p + c] = color[c] / 255.0;
  }
  std::vector<double> heights, bumped_xyz(3 * n), bumped_normals(3 * n);
  if (bump_series_) {
    heights.resize(pattern.size());
    for (std::size_t v = 0; v < pattern.size(); ++v)
      heights[v] = std::clamp((pattern[v] - lo) / (hi - lo), 0.0, 1.0);
    const auto bumped = geom::bump_map(piece.mesh, heights, render_.bump_scale);
    for (std::size_t p = 0; p < n; ++p)
      for (int axis = 0; axis < 3; ++axis) {
        bumped_xyz[3 * p + axis] = bumped.positions[piece.written_vertices[p]][axis];
        bumped_normals[3 * p + axis] = bumped.normals[piece.written_vertices[p]][axis];
      }
  }
  io::SurfacePiece surface{xyz, piece.written_connectivity, {}, {}};
  surface.point_fields.push_back({"pattern", 1, values});
  surface.point_fields.push_back({"color", 3, rgb});
  if (bump_series_)
    surface.point_fields.push_back({"bump_normals", 3, bumped_normals});
  const auto file = io::write_parallel_surface(comm_, output_dir_ / "frames", "surface_" + name,
                                               surface, io::SurfaceFormat::vtp);
  surface_series_->add(time, std::filesystem::relative(file, output_dir_).string());
  if (bump_series_) {
    io::SurfacePiece bumped{bumped_xyz, piece.written_connectivity, {}, {}};
    bumped.point_fields.push_back({"pattern", 1, values});
    bumped.point_fields.push_back({"color", 3, rgb});
    bumped.point_fields.push_back({"Normals", 3, bumped_normals});
    const auto bump_file = io::write_parallel_surface(comm_, output_dir_ / "frames", "bump_" + name,
                                                      bumped, io::SurfaceFormat::vtp);
    bump_series_->add(time, std::filesystem::relative(bump_file, output_dir_).string());
  }
}

void PatternFrames::write_cells(const std::string& name, double time, const FrameData& data) {
  // Values at the view's cells, one field at a time through the same ghosted vector.
  const auto view_values = [&](std::span<const double> owned) {
    near_pieces_->set_owned(owned);
    return std::vector<double>(near_pieces_->local().begin(), near_pieces_->local().end());
  };
  std::vector<std::vector<double>> fields{view_values(data.shown)};
  for (const auto& species : data.species)
    fields.push_back(view_values(species));

  std::vector<double> xyz;
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> cell_ids;
  std::vector<std::vector<double>> cell_values(fields.size());
  for (const auto& piece : cells_.pieces()) {
    const std::int64_t first = std::int64_t(xyz.size() / 3);
    for (const auto& p : piece.polygon)
      xyz.insert(xyz.end(), p.data(), p.data() + 3);
    // Voronoi pieces are convex: a fan from the first corner triangulates them.
    for (std::size_t k = 1; k + 1 < piece.polygon.size(); ++k) {
      connectivity.insert(connectivity.end(),
                          {first, first + std::int64_t(k), first + std::int64_t(k) + 1});
      cell_ids.push_back(cells_.view_ids()[piece.seed]);
      for (std::size_t f = 0; f < fields.size(); ++f)
        cell_values[f].push_back(fields[f][piece.seed]);
    }
  }
  io::SurfacePiece surface{xyz, connectivity, {}, {}};
  surface.cell_fields.push_back({"cell_id", 1, cell_ids});
  surface.cell_fields.push_back({"pattern", 1, cell_values[0]});
  for (std::size_t s = 0; s < data.species_names.size(); ++s)
    surface.cell_fields.push_back({data.species_names[s], 1, cell_values[s + 1]});
  const auto file = io::write_parallel_surface(comm_, output_dir_ / "frames", "cells_" + name,
                                               surface, io::SurfaceFormat::vtp);
  cells_series_->add(time, std::filesystem::relative(file, output_dir_).string());
}

} // namespace texsim::pipelines::turk_rd
