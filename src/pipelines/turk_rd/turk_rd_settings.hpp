#pragma once
/// The `turk_rd:` section of a config (docs/turk_rd.md has every key):
///   turk_rd:
///     mesh: {generator: icosphere, level: 4}            # or {file: data/meshes/cow.off}
///     cells: {count: 20000, relaxation: {iterations: 40}}
///     diffusion_scale: "1 + 0.5 * (x > 0.2)"            # f(x, y, z): faster diffusion, wider
///     stripes (or of a per-vertex array of the mesh file named in mesh_fields: [width]) stages: #
///     run in file order: a cascade
///       spots: {model: {type: turing_spots, s: 0.05}, steps: 20000, dt: 1.0}
///       rosettes: {model: {...}, steps: 8000, active: "spots_b < 4", show: "b"}
///     render: {colors: [[0.93, 0.78, 0.52], [0.1, 0.07, 0.05]], radius: 2, bump: 0.01}
#include "geom/mesh_source.hpp"
#include "geom/surface_cells.hpp"
#include "pipelines/turk_rd/pattern_colormap.hpp"
#include "rd/reaction_model.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace texsim::pipelines::turk_rd {

/// Cells frozen at the start of a stage, holding chosen values (Turk's initiators): the cells
/// nearest to `at` (and all within `radius` of it), or every cell where `region` is nonzero.
struct InitiatorSettings {
  std::string name;
  std::optional<geom::Vec3> at;
  double radius = 0.0;
  std::string region; ///< expression of x, y, z and the mesh fields; empty when `at` is used
  std::vector<std::pair<std::size_t, double>> values; ///< (species index, value held)
  std::string key_path;                               ///< "turk_rd.stages.s.initiators.head"
};

/// One system of a cascade.
struct StageSettings {
  std::string name;
  std::shared_ptr<rd::ReactionModel> model;
  std::vector<std::string> species;
  std::int64_t steps = 10000;
  double dt = 1.0;
  /// turk_rd.stability_safety: a dt above the explicit stability limit of the cells is split into
  /// substeps of at most this fraction of the limit (CellRdSolver::substeps).
  double stability_safety = 0.9;
  /// Cells where this is zero keep their values during the stage (expression of x, y, z, the mesh
  /// fields and the earlier stages' final values "<stage>_<species>"); empty: all cells change.
  std::string active;
  /// active_start: "carried" (the active cells continue from the earlier stage's values) or
  /// "initial" (they restart from this stage's model initial state; frozen cells keep theirs).
  bool active_start_initial = false;
  /// The scalar shown and rendered (expression of this stage's species, x, y, z and earlier
  /// stages' "<stage>_<species>").
  std::string show;
  /// rings: {regions, marks}: two expressions over the same variables as `show`; where they are
  /// nonzero are the regions (e.g. an earlier stage's large spots) and the marks whose radial
  /// profile summary.json reports (measure_rings). Empty: not measured.
  std::string ring_regions;
  std::string ring_marks;
  /// network: {web}: an expression over `show`'s variables whose nonzero cells are a web between
  /// patches (Turk's giraffe), measured by measure_web. Empty: not measured.
  std::string network_web;
  /// stripes_axis: [x, y, z]: a body axis against which summary.json measures the direction of
  /// the shown pattern's stripes (stripes_across_axis). Unset: not measured.
  std::optional<geom::Vec3> stripes_axis;
  std::vector<InitiatorSettings> initiators;
  std::string key_path; ///< "turk_rd.stages.<name>"
};

struct RenderSettings {
  PatternColormap colormap{tan_to_dark_stops()};
  std::optional<std::array<double, 2>> range; ///< value range of the colormap; default per frame
  double radius_spacings = 2.0;               ///< Turk's weighting radius in cell spacings
  int subdivision_levels = 0; ///< Loop subdivision of the input mesh before rendering
  double bump_scale = 0.0;    ///< displacement at the top of the range (model units); 0: no bumps
};

struct TurkRdSettings {
  geom::MeshSource mesh;
  geom::SurfaceCellsSettings cells;
  /// One-component point arrays of mesh.file, sampled at the cells: variables of diffusion_scale,
  /// the initiators' regions and the stages' `active` under their array names.
  std::vector<std::string> mesh_fields;
  std::string diffusion_scale = "1";
  std::vector<StageSettings> stages;
  RenderSettings render;

  std::int64_t total_steps() const;
};

/// Names stage expressions may use for earlier stages' results: "<stage>_<species>" for every
/// species of stages [0, stage).
std::vector<std::string> earlier_stage_names(const std::vector<StageSettings>& stages,
                                             std::size_t stage);

/// Reads and validates the section (models and every expression are built once to check them).
TurkRdSettings read_turk_rd_settings(const ConfigSection& section, std::uint64_t seed);

} // namespace texsim::pipelines::turk_rd
