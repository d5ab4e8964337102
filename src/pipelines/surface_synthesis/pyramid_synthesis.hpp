#pragma once
/// The multiresolution loop of Wei-Levoy (Table 3, lines 6-9): levels from coarse to fine, on
/// each the stencils, the colour classes of both passes and the searches, with hooks where the
/// pipeline checkpoints, stops and writes frames. Tests drive it on given pyramids (flat grids).
#include "core/stage_timers.hpp"
#include "img/image.hpp"
#include "par/comm.hpp"
#include "pipelines/surface_synthesis/level_synthesizer.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"
#include "pipelines/surface_synthesis/orientation_field.hpp"
#include "pipelines/surface_synthesis/synthesis_checkpoint.hpp"

#include <functional>
#include <optional>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// Everything the loop reads; per-level vectors are indexed by level (0 = finest).
struct PyramidSynthesisInput {
  const std::vector<RetiledLevel>& pyramid;
  const std::vector<std::vector<geom::Vec3>>& directions; ///< of this rank's run of each level
  /// Level k's parent faces on level k + 1 of this rank's run of level k (empty for the coarsest).
  const std::vector<std::vector<ParentFace>>& parents;
  const std::vector<img::RgbImage>& exemplar; ///< G_a, as many levels as the pyramid
  std::vector<NeighbourhoodShape> shapes{};   ///< per level, 0 = finest
  SearchMethod method = SearchMethod::exhaustive;
  ExemplarBorder border = ExemplarBorder::toroidal;
  std::uint64_t seed = 1;
  /// Measure the neighbourhood error of the random start and of the result (exact searches over
  /// the finest level: benchmarks leave them out of synthesis times).
  bool measure_quality = true;
};

struct PyramidSynthesisHooks {
  /// After class `c` of `pass` on `level` (every rank).
  std::function<void(int level, Pass pass, std::int32_t c, std::int32_t classes)> after_class;
  /// After a pass (also a skipped one) on `level`.
  std::function<void(int level, Pass pass)> after_pass;
};

struct PyramidSynthesisReport {
  struct Level {
    int level = 0;
    std::int32_t classes[2] = {0, 0}; ///< pass 1, pass 2 (0: pass skipped)
    double uncovered_fraction = 0;
    /// Distinct colours the level ended with; 1: it collapsed to one colour (the pipeline warns
    /// when the finest level did).
    std::int64_t distinct_colours = 0;
  };
  std::vector<Level> levels;
  double neighbourhood_error = 0; ///< finest level, after synthesis
  double random_start_error = 0;  ///< finest level before synthesis (fresh runs only)
  std::size_t search_bytes = 0;   ///< largest level's tables and search structures
  /// Most colours a rank held beside its run on one level (its halo and the coarser vertices it
  /// read), over ranks and levels.
  std::int64_t halo_vertices = 0;
};

/// Every level starts as random copies of its exemplar level's pixels (Wei-Levoy Table 3, line 5;
/// Philox by level and vertex id): the coarsest level keeps them. Each level's run of `rank`.
std::vector<LevelColours> random_start(const std::vector<RetiledLevel>& pyramid,
                                       const std::vector<img::RgbImage>& exemplar,
                                       std::uint64_t seed, int rank);

/// Synthesises `colours` (this rank's runs, from random_start or a checkpoint) from `resume` on
/// (nullopt: from the start); `timers` gets "stencils" and "synthesis". Collective.
PyramidSynthesisReport synthesize_pyramid(const par::Comm& comm, const PyramidSynthesisInput& input,
                                          std::vector<LevelColours>& colours,
                                          const std::optional<SynthesisPosition>& resume,
                                          const PyramidSynthesisHooks& hooks, StageTimers& timers);

} // namespace texsim::pipelines::surface_synthesis
