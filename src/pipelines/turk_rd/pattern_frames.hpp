#pragma once
/// The ParaView output of a turk_rd run, one frame per call, each in its own .pvd series:
///   - turk_rd_surface.pvd: the input mesh (optionally Loop-subdivided) with the pattern rendered
///     at its vertices by Turk's weighted sum of nearby cells, and its colour-mapped RGB;
///   - turk_rd_cells.pvd: the cells themselves (their Voronoi polygons on the input triangles)
///     with every species and the shown value;
///   - turk_rd_bump.pvd (when render.bump > 0): the bump-mapped surface, displaced along the
///     normals by the pattern, with the perturbed normals.
/// Each rank writes the triangles it was given (a Morton partition of the render mesh) and
/// fetches the cells near them through ghosted vectors.
#include "geom/surface_cells.hpp"
#include "geom/triangle_mesh.hpp"
#include "io/pvd_series.hpp"
#include "par/comm.hpp"
#include "par/ghosted_vector.hpp"
#include "pipelines/turk_rd/pattern_sampler.hpp"
#include "pipelines/turk_rd/render_piece.hpp"
#include "pipelines/turk_rd/turk_rd_settings.hpp"

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace texsim::pipelines::turk_rd {

/// Per-cell data of one frame (owned cells).
struct FrameData {
  double time = 0;
  std::span<const double> shown;                 ///< the stage's `show` value
  const std::vector<std::string>& species_names; ///< of the running stage
  const std::vector<std::vector<double>>& species;
};

class PatternFrames {
public:
  /// Builds the render mesh (the input's creases kept sharp when it is subdivided), its partition
  /// and the samplers. With `restart_time` the series are continued (entries after that time
  /// dropped), otherwise started afresh. Collective.
  PatternFrames(const par::Comm& comm, const geom::DistributedTriangles& input,
                const geom::SurfaceCells& cells, const RenderSettings& render,
                const std::filesystem::path& output_dir, std::optional<double> restart_time);
  ~PatternFrames();

  /// Writes frame `step`. Collective.
  void write(std::int64_t step, const FrameData& data);

  /// The .pvd files written.
  std::vector<std::filesystem::path> series() const;

private:
  void write_surface(const std::string& name, double time, std::span<const double> pattern,
                     double lo, double hi);
  void write_cells(const std::string& name, double time, const FrameData& data);

  const par::Comm& comm_;
  const geom::SurfaceCells& cells_;
  const RenderSettings& render_;
  std::filesystem::path output_dir_;
  std::unique_ptr<RenderPiece> piece_;
  std::unique_ptr<PatternSampler> sampler_;
  std::unique_ptr<par::GhostedVector> near_surface_; ///< owned cells + cells near the piece
  std::unique_ptr<par::GhostedVector> near_pieces_;  ///< the SurfaceCells view
  std::unique_ptr<io::PvdSeries> surface_series_, cells_series_, bump_series_;
};

} // namespace texsim::pipelines::turk_rd
