#include "pipelines/turk_rd/turk_rd_pipeline.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "core/stop_signal.hpp"
#include "geom/distributed_mesh_fields.hpp"
#include "geom/mesh_fields.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/point_expression.hpp"
#include "par/checkpoint_clock.hpp"
#include "par/collective.hpp"
#include "par/global_median.hpp"
#include "par/global_range.hpp"
#include "pipelines/turk_rd/cascade_checkpoint.hpp"
#include "pipelines/turk_rd/cell_rd_solver.hpp"
#include "pipelines/turk_rd/initiators.hpp"
#include "pipelines/turk_rd/pattern_frames.hpp"
#include "pipelines/turk_rd/pattern_shapes.hpp"
#include "pipelines/turk_rd/ring_profile.hpp"
#include "pipelines/turk_rd/stripe_direction.hpp"
#include "pipelines/turk_rd/web_network.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace texsim::pipelines::turk_rd {
namespace {

using FieldMap = std::map<std::string, std::vector<double>>;

std::vector<double> owned_xyz(const geom::SurfaceCells& cells) {
  std::vector<double> xyz;
  for (const auto& p : cells.points())
    xyz.insert(xyz.end(), p.position.data(), p.position.data() + 3);
  return xyz;
}

std::vector<std::span<const double>> columns(const FieldMap& fields,
                                             const std::vector<std::string>& names) {
  std::vector<std::span<const double>> result;
  for (const auto& name : names)
    result.emplace_back(fields.at(name));
  return result;
}

/// The point arrays `settings.mesh_fields` of the mesh file at the owned cells: interpolated at
/// the closest point of the file's surface (scaled as the mesh section says; refinement and noise
/// move the cells off it). Collective.
FieldMap sample_mesh_fields(const par::Comm& comm, const TurkRdSettings& settings,
                            const geom::SurfaceCells& cells) {
  FieldMap fields;
  if (settings.mesh_fields.empty())
    return fields;
  // The file on rank 0 only; each rank gets the part of it near its cells.
  const geom::DistributedMeshFields file(comm, settings.mesh, settings.mesh_fields);
  std::vector<geom::Vec3> points;
  for (const auto& p : cells.points())
    points.push_back(p.position);
  auto values = file.sample(points);
  for (std::size_t k = 0; k < settings.mesh_fields.size(); ++k)
    fields[settings.mesh_fields[k]] = std::move(values[k]);
  return fields;
}

/// f at the owned cells, from position and mesh fields; must be positive everywhere. Collective.
std::vector<double> diffusion_scale(const par::Comm& comm, const TurkRdSettings& settings,
                                    const geom::SurfaceCells& cells, const FieldMap& mesh_fields) {
  std::vector<double> scale;
  par::run_collectively(comm, [&] {
    const auto xyz = owned_xyz(cells);
    scale = geom::PointExpression(settings.diffusion_scale, settings.mesh_fields,
                                  "turk_rd.diffusion_scale")
                .evaluate(xyz, columns(mesh_fields, settings.mesh_fields));
    for (std::size_t i = 0; i < scale.size(); ++i)
      if (!(scale[i] > 0.0) || !std::isfinite(scale[i]))
        throw InputError(log::cat("turk_rd.diffusion_scale: expected a positive value at every "
                                  "cell, got ",
                                  scale[i], " at (", xyz[3 * i], ", ", xyz[3 * i + 1], ", ",
                                  xyz[3 * i + 2], ")"));
  });
  return scale;
}

/// Throws InputError naming the stage's dt when a value left the finite range: the explicit
/// reaction step is unstable for this dt. Collective.
void check_finite(const par::Comm& comm, const StageSettings& stage, std::int64_t step,
                  const std::vector<std::vector<double>>& species) {
  int bad = 0;
  for (const auto& values : species)
    for (const double v : values)
      bad |= !std::isfinite(v);
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, comm.raw);
  if (bad)
    throw InputError(log::cat(stage.key_path,
                              ".dt: the explicit step diverged (non-finite values "
                              "after step ",
                              step, " of stage '", stage.name, "'); use a smaller dt than ",
                              stage.dt));
}

/// Logs the explicit substeps a stage takes when its dt is above the cells' stability limit, and
/// refuses a dt that would need more than kMaxSubsteps of them. Collective (every rank holds the
/// same limit).
void log_substeps(const StageSettings& stage, const CellRdSolver& solver) {
  constexpr std::int64_t kMaxSubsteps = 1000;
  if (solver.substeps() > kMaxSubsteps) {
    InputError error(log::cat(
        stage.key_path, ".dt: ", stage.dt, " needs ", solver.substeps(),
        " explicit substeps (stability limit of these cells ", solver.max_stable_dt(),
        "); expected at most ", kMaxSubsteps,
        ": some cells couple across thin parts or slivers of the mesh; use a smaller dt, fewer "
        "cells or mesh.remesh"));
    error.mark_on_all_ranks();
    throw error;
  }
  if (solver.substeps() > 1)
    log::info(log::cat("stage '", stage.name, "': dt ", stage.dt,
                       " is above the explicit stability limit ", solver.max_stable_dt(),
                       " of these cells: ", solver.substeps(), " substeps of ", solver.substep_dt(),
                       " per step (turk_rd.stability_safety ", stage.stability_safety, ")"));
}

/// One stage of the cascade set up on the cells: its solver, frozen cells and start values.
class StageRun {
public:
  /// `fields` holds the earlier stages' results, the carried species and the mesh fields.
  StageRun(const par::Comm& comm, const geom::SurfaceCells& cells, const StageSettings& stage,
           const std::vector<std::string>& earlier_names,
           const std::vector<std::string>& mesh_field_names, const FieldMap& fields,
           std::span<const double> scale, bool fresh)
      : stage_(stage), earlier_names_(earlier_names),
        solver_(comm, cells, *stage.model, scale, stage.dt, stage.stability_safety),
        xyz_(owned_xyz(cells)) {
    std::vector<char> frozen(std::size_t(cells.owned_count()), 0);
    if (!stage.active.empty()) {
      auto names = earlier_names;
      names.insert(names.end(), mesh_field_names.begin(), mesh_field_names.end());
      const auto active = geom::PointExpression(stage.active, names, stage.key_path + ".active")
                              .evaluate(xyz_, columns(fields, names));
      for (std::size_t i = 0; i < frozen.size(); ++i)
        frozen[i] = active[i] == 0.0;
    }
    // Start values: a species carried over from the stage before keeps its values (the fields
    // hold them under their plain names), except in the active cells of a stage that restarts
    // them from the model's initial state; on a restart all come from the checkpoint.
    for (std::size_t s = 0; s < stage.species.size(); ++s) {
      const auto found = fields.find(stage.species[s]);
      if (found == fields.end()) {
        TEXSIM_VERIFY(fresh, "restart without values of species " << stage.species[s]);
        continue;
      }
      auto values = found->second;
      if (fresh && stage.active_start_initial) {
        const auto initial = solver_.owned_values(s);
        for (std::size_t i = 0; i < values.size(); ++i)
          if (!frozen[i])
            values[i] = initial[i];
      }
      solver_.set_owned_values(s, values);
    }
    for (const auto& initiator : stage.initiators) {
      const auto selected = select_initiator_cells(comm, cells, initiator, mesh_field_names,
                                                   columns(fields, mesh_field_names));
      for (std::size_t i = 0; i < frozen.size(); ++i)
        frozen[i] |= selected[i];
      if (!fresh)
        continue; // the checkpoint holds the initiators' values already
      for (const auto& [species, value] : initiator.values) {
        auto values = solver_.owned_values(species);
        for (std::size_t i = 0; i < values.size(); ++i)
          if (selected[i])
            values[i] = value;
        solver_.set_owned_values(species, values);
      }
    }
    solver_.set_frozen(std::move(frozen));
    log_substeps(stage, solver_);
  }

  CellRdSolver& solver() { return solver_; }

  /// The running stage's species under their plain names.
  FieldMap species_fields() const {
    FieldMap fields;
    for (std::size_t s = 0; s < solver_.species_count(); ++s)
      fields[stage_.species[s]] = solver_.owned_values(s);
    return fields;
  }

  /// The stage's `show` value at the owned cells.
  std::vector<double> shown(const FieldMap& earlier) const {
    return evaluate(stage_.show, "show", earlier);
  }

  /// The ring profile the stage's `rings` section asks for. Collective.
  RingProfile rings(const par::Comm& comm, const geom::SurfaceCells& cells,
                    const FieldMap& earlier) const {
    return measure_rings(comm, cells, marks(stage_.ring_regions, "rings.regions", earlier),
                         marks(stage_.ring_marks, "rings.marks", earlier));
  }

  /// The web measure the stage's `network` section asks for. Collective.
  WebNetwork network(const par::Comm& comm, const geom::SurfaceCells& cells,
                     const FieldMap& earlier) const {
    return measure_web(comm, cells, marks(stage_.network_web, "network.web", earlier));
  }

private:
  /// Where `expression` is nonzero at the owned cells.
  std::vector<char> marks(const std::string& expression, const std::string& key,
                          const FieldMap& earlier) const {
    const auto values = evaluate(expression, key, earlier);
    std::vector<char> marked(values.size());
    std::transform(values.begin(), values.end(), marked.begin(),
                   [](double v) { return char(v != 0); });
    return marked;
  }

  /// `expression` over the stage's species, x, y, z and the earlier stages' results ("show"'s
  /// variables) at the owned cells; `key` names it under the stage's key path in errors.
  std::vector<double> evaluate(const std::string& expression, const std::string& key,
                               const FieldMap& earlier) const {
    FieldMap all = species_fields();
    all.insert(earlier.begin(), earlier.end());
    auto names = stage_.species;
    names.insert(names.end(), earlier_names_.begin(), earlier_names_.end());
    return geom::PointExpression(expression, names, stage_.key_path + "." + key)
        .evaluate(xyz_, columns(all, names));
  }

  const StageSettings& stage_;
  std::vector<std::string> earlier_names_;
  CellRdSolver solver_;
  std::vector<double> xyz_;
};

} // namespace

void TurkRdPipeline::configure(const ConfigSection& section, const RunSettings& run) {
  settings_ = read_turk_rd_settings(section, run.seed);
}

void TurkRdPipeline::run(RunContext& ctx) {
  const auto& comm = ctx.comm;
  const auto& run = ctx.settings;
  auto& report = ctx.report;

  // Rank 0 builds the surface and splits it: every rank keeps its share of the triangles and
  // fetches the others' near its cells when it needs them (geom::DistributedTriangles).
  std::unique_ptr<geom::DistributedTriangles> surface;
  {
    auto stage = ctx.timers.scope("mesh");
    geom::TriangleMesh whole;
    std::vector<char> creases; // mesh.crease_angle's, kept sharp by render.subdivision_levels
    geom::MeshBuildReport built;
    par::run_collectively(comm, [&] {
      if (comm.is_root())
        whole = geom::build_mesh(settings_.mesh, run.seed, &built, &creases);
    });
    if (comm.is_root()) // the summary and the log are rank 0's
      geom::record_mesh_build(built, report);
    surface = std::make_unique<geom::DistributedTriangles>(
        geom::DistributedTriangles::from_root(comm, whole, creases));
  }
  std::unique_ptr<geom::SurfaceCells> cells_owner;
  {
    auto stage = ctx.timers.scope("retiling");
    cells_owner = std::make_unique<geom::SurfaceCells>(comm, *surface, run.seed, settings_.cells);
  }
  const auto& cells = *cells_owner;
  {
    double local_area = 0, total_cell_area = 0;
    for (const double a : cells.areas())
      local_area += a;
    MPI_Allreduce(&local_area, &total_cell_area, 1, MPI_DOUBLE, MPI_SUM, comm.raw);
    const double mean_area = cells.surface_area() / double(cells.global_count());
    const auto area_range = par::global_range(comm, cells.areas());
    const double area_median = par::global_median(comm, cells.areas());
    const auto coupling_range = par::global_range(comm, cells.couplings());
    const auto& q = cells.quality();
    const auto& relaxation = cells.relaxation();
    report.metric("cells", {{"count", cells.global_count()},
                            {"surface_area", cells.surface_area()},
                            {"cell_area_sum_relative_error",
                             (total_cell_area - cells.surface_area()) / cells.surface_area()},
                            {"spacing", cells.spacing()},
                            {"area_min_over_mean", area_range.min / mean_area},
                            {"area_max_over_mean", area_range.max / mean_area},
                            {"area_min", area_range.min},
                            {"area_median", area_median},
                            {"area_max", area_range.max},
                            {"coupling_max", coupling_range.max},
                            {"relaxation_radius", relaxation.radius},
                            {"relaxation_iterations", settings_.cells.relaxation.iterations},
                            {"relaxation_halo_max", relaxation.max_halo_points},
                            {"relaxation_window_fetches", relaxation.window_fetches},
                            {"relaxation_window_triangles_max", relaxation.window_triangles_max},
                            {"triangles", surface->global_count()}});
    report.metric("partition", {{"method", "morton"},
                                {"edge_cut", q.edge_cut},
                                {"imbalance", q.imbalance},
                                {"ghosts_max", q.ghosts_max}});
    log::info(log::cat("retiling: ", cells.global_count(), " cells on ", surface->global_count(),
                       " triangles, cell areas sum to the surface area within ",
                       std::abs(total_cell_area - cells.surface_area()) / cells.surface_area(),
                       ", areas ", area_range.min / mean_area, " to ", area_range.max / mean_area,
                       " of the mean (min ", area_range.min, ", median ", area_median, ", max ",
                       area_range.max, "), couplings up to ", coupling_range.max,
                       "; partition edge cut ", q.edge_cut, ", imbalance ", q.imbalance));
  }

  const auto mesh_fields = sample_mesh_fields(comm, settings_, cells);
  const auto scale = diffusion_scale(comm, settings_, cells, mesh_fields);
  const auto& stages = settings_.stages;
  io::CheckpointStore store(comm, run.output_dir / "checkpoints", run.config_hash,
                            run.checkpoint_keep);
  CascadeState state;
  std::unique_ptr<PatternFrames> frames;
  std::vector<std::int64_t> stage_begin{0};
  std::vector<double> stage_time{0.0};
  for (const auto& stage : stages) {
    stage_begin.push_back(stage_begin.back() + stage.steps);
    stage_time.push_back(stage_time.back() + double(stage.steps) * stage.dt);
  }
  {
    auto stage = ctx.timers.scope("setup");
    std::optional<double> restart_time;
    if (run.restart) {
      const auto reader = store.resolve_for_restart(*run.restart);
      const auto stage_index = std::size_t(reader.attribute_int64("stage"));
      if (stage_index >= stages.size())
        throw InputError(reader.path().string() + ": stage " + std::to_string(stage_index) +
                         " of a cascade with more stages");
      auto fields = earlier_stage_names(stages, stage_index);
      fields.insert(fields.end(), stages[stage_index].species.begin(),
                    stages[stage_index].species.end());
      state = load_cascade(reader, cells, fields);
      restart_time = stage_time[state.stage] + double(state.stage_step) * stages[state.stage].dt;
      log::info(log::cat("restarted from ", reader.path().string(), " in stage '",
                         stages[state.stage].name, "' after ", state.stage_step, " steps"));
    }
    frames = std::make_unique<PatternFrames>(comm, *surface, cells, settings_.render,
                                             run.output_dir, restart_time);
    surface.reset(); // the cells and the render piece hold all the steps need
  }

  FieldMap earlier; // "<stage>_<species>" of finished stages
  for (const auto& [name, values] : state.fields)
    if (name.find('_') != std::string::npos &&
        std::any_of(stages.begin(), stages.begin() + std::ptrdiff_t(state.stage),
                    [&](const StageSettings& s) { return name.rfind(s.name + "_", 0) == 0; }))
      earlier[name] = values;
  FieldMap carried = state.fields; // start values of the next stage, by plain species name
  nlohmann::json stage_metrics = nlohmann::json::object();
  par::CheckpointClock clock(comm, run.checkpoint_every, run.checkpoint_minutes);
  Progress progress("turk_rd", settings_.total_steps(), "steps");

  for (std::size_t k = state.stage; k < stages.size(); ++k) {
    const auto& stage = stages[k];
    const bool fresh = !(run.restart && k == state.stage);
    const std::int64_t first_step = fresh ? 0 : state.stage_step;
    StageRun stage_run(
        comm, cells, stage, earlier_stage_names(stages, k), settings_.mesh_fields,
        [&] {
          FieldMap all = carried;
          all.insert(earlier.begin(), earlier.end());
          all.insert(mesh_fields.begin(), mesh_fields.end());
          return all;
        }(),
        scale, fresh);
    auto& solver = stage_run.solver();
    std::vector<double> initial_integral;
    for (std::size_t s = 0; s < solver.species_count(); ++s)
      initial_integral.push_back(solver.integral(s));
    log::info(log::cat("stage '", stage.name, "': ", stage.steps - first_step, " steps of dt ",
                       stage.dt, ", species ", solver.species_count(), ", frozen cells ",
                       solver.frozen_count(), " on rank 0"));

    const auto write_frame = [&](std::int64_t stage_step) {
      auto timer = ctx.timers.scope("output");
      std::vector<std::vector<double>> species;
      for (std::size_t s = 0; s < solver.species_count(); ++s)
        species.push_back(solver.owned_values(s));
      check_finite(comm, stage, stage_step, species);
      const auto shown = stage_run.shown(earlier);
      frames->write(stage_begin[k] + stage_step,
                    {stage_time[k] + double(stage_step) * stage.dt, shown, stage.species, species});
    };
    if (k == 0 && fresh)
      write_frame(0);
    for (std::int64_t step = first_step; step < stage.steps; ++step) {
      {
        auto timer = ctx.timers.scope("rd_step");
        solver.step(stage_time[k] + double(step) * stage.dt);
      }
      const std::int64_t done = step + 1;
      const std::int64_t global = stage_begin[k] + done;
      if (global % run.output_every == 0 || done == stage.steps)
        write_frame(done);
      const auto decision = clock.after_step(global);
      if (decision.checkpoint) {
        auto timer = ctx.timers.scope("checkpoint");
        CascadeState now{k, done, stage_run.species_fields()};
        now.fields.insert(earlier.begin(), earlier.end());
        save_cascade(store, global, cells, now);
      }
      if (decision.stop)
        throw CheckpointedStop(decision.signal_number,
                               log::cat("in stage '", stage.name, "' after step ", done));
      progress.update(global);
    }

    auto timer = ctx.timers.scope("finish");
    nlohmann::json species_metrics = nlohmann::json::object();
    carried = stage_run.species_fields();
    for (std::size_t s = 0; s < solver.species_count(); ++s) {
      const auto& values = carried.at(stage.species[s]);
      const auto range = par::global_range(comm, values);
      const auto shapes = measure_pattern(comm, cells, values);
      species_metrics[stage.species[s]] = {{"initial_integral", initial_integral[s]},
                                           {"final_integral", solver.integral(s)},
                                           {"min", range.min},
                                           {"max", range.max},
                                           {"regions_above_mean", shapes.regions},
                                           {"cells_per_region", shapes.mean_cells},
                                           {"median_elongation", shapes.median_elongation},
                                           {"max_elongation", shapes.max_elongation},
                                           {"weighted_elongation", shapes.weighted_elongation},
                                           {"median_aspect", shapes.median_aspect},
                                           {"weighted_aspect", shapes.weighted_aspect}};
    }
    const auto shown_shapes = measure_pattern(comm, cells, stage_run.shown(earlier));
    stage_metrics[stage.name] = {{"steps", stage.steps},
                                 {"dt", stage.dt},
                                 {"max_stable_dt", solver.max_stable_dt()},
                                 {"substeps", solver.substeps()},
                                 {"frozen_cells_rank0", solver.frozen_count()},
                                 {"species", species_metrics},
                                 {"shown",
                                  {{"expression", stage.show},
                                   {"regions_above_mean", shown_shapes.regions},
                                   {"median_elongation", shown_shapes.median_elongation},
                                   {"median_aspect", shown_shapes.median_aspect}}}};
    if (!stage.ring_regions.empty()) {
      const RingProfile rings = stage_run.rings(comm, cells, earlier);
      stage_metrics[stage.name]["rings"] = {{"regions", rings.regions},
                                            {"marked_by_radius", rings.marked_by_radius},
                                            {"centre_marked", rings.centre_marked},
                                            {"rim_marked", rings.rim_marked},
                                            {"rim_sectors_marked", rings.rim_sectors_marked}};
    }
    if (stage.stripes_axis)
      stage_metrics[stage.name]["stripes_across_axis"] =
          stripes_across_axis(comm, cells, stage_run.shown(earlier), *stage.stripes_axis);
    if (!stage.network_web.empty()) {
      const WebNetwork web = stage_run.network(comm, cells, earlier);
      stage_metrics[stage.name]["network"] = {{"web_area_fraction", web.web_area_fraction},
                                              {"web_components", web.web_components},
                                              {"largest_web_fraction", web.largest_web_fraction},
                                              {"patches", web.patches},
                                              {"mean_web_width", web.mean_web_width},
                                              {"median_patch_diameter", web.median_patch_diameter}};
    }
    for (const auto& [name, values] : carried)
      earlier[stage.name + "_" + name] = values;
  }
  progress.finish();
  report.metric("stages", stage_metrics);
  report.metric("steps", settings_.total_steps());
  for (const auto& path : frames->series())
    report.output(path.string());
}

} // namespace texsim::pipelines::turk_rd
