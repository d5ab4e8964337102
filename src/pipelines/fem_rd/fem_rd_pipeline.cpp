#include "pipelines/fem_rd/fem_rd_pipeline.hpp"

#include "core/log.hpp"
#include "core/progress.hpp"
#include "core/stop_signal.hpp"
#include "geom/distributed_measures.hpp"
#include "geom/distributed_mesh_fields.hpp"
#include "geom/distributed_noise.hpp"
#include "geom/mesh_source.hpp"
#include "io/pvd_series.hpp"
#include "par/checkpoint_clock.hpp"
#include "par/collective.hpp"
#include "par/global_range.hpp"
#include "par/record_exchange.hpp"
#include "pipelines/fem_rd/frame_writer.hpp"
#include "pipelines/fem_rd/geometry_smoother.hpp"
#include "pipelines/fem_rd/locked_phase.hpp"
#include "pipelines/fem_rd/pattern_orientation.hpp"
#include "pipelines/fem_rd/pattern_regions.hpp"
#include "pipelines/fem_rd/state_checkpoint.hpp"

namespace texsim::pipelines::fem_rd {
namespace {

/// Smoothing steps happen at the start of RD steps 0, every, 2*every, ... until `steps` are done.
bool smooths_at(const FemRdSettings& settings, std::int64_t step) {
  return settings.smoothing && step % settings.smoothing_every == 0 &&
         step / settings.smoothing_every < settings.smoothing_steps;
}

/// The RD matrices are rebuilt at steps 0, rebuild_every, ... when the surface was smoothed since
/// the previous one (matrices of an unchanged surface would be the same bits); the same answer on
/// every rank and after a restart.
bool rebuilds_at(const FemRdSettings& settings, std::int64_t step) {
  if (!settings.smoothing || step % settings.rebuild_every != 0)
    return false;
  for (std::int64_t s = std::max<std::int64_t>(0, step - settings.rebuild_every + 1); s <= step;
       ++s)
    if (smooths_at(settings, s))
      return true;
  return false;
}

struct SurfaceMeasures {
  double area = 0;
  double normal_deviation_deg = 0;
};

SurfaceMeasures measure(const geom::DistributedMesh& mesh) {
  return {geom::total_area(mesh), geom::mean_normal_deviation_deg(mesh)};
}

} // namespace

void FemRdPipeline::configure(const ConfigSection& section, const RunSettings& run) {
  settings_ = read_fem_rd_settings(section);
  model_ = rd::make_reaction_model(section.section("model"), run.seed);
  if (settings_.diffusion) // its formulas and species checked before the run
    (void)DiffusionField(*settings_.diffusion, model_->species());
}

void FemRdPipeline::run(RunContext& ctx) {
  const auto& comm = ctx.comm;
  const auto& run = ctx.settings;
  auto& report = ctx.report;

  std::unique_ptr<geom::DistributedMesh> mesh;
  {
    geom::SurfacePlan surface;
    {
      // Rank 0 builds the coarse surface (serial) ...
      auto stage = ctx.timers.scope("mesh");
      geom::MeshBuildReport built;
      par::run_collectively(comm, [&] {
        if (comm.is_root())
          surface = geom::plan_surface(settings_.mesh, &built);
      });
      if (comm.is_root()) // the summary and the log are rank 0's
        geom::record_mesh_build(built, report);
      par::broadcast_records(comm, surface.refinement);
    }
    // ... sends each rank its part (partition.root_s of it serial on rank 0), which the rank
    // refines.
    auto stage = ctx.timers.scope("distribution");
    mesh = std::make_unique<geom::DistributedMesh>(comm, surface.coarse, settings_.partition,
                                                   surface.refinement, surface.creases);
    surface = {};
    if (settings_.mesh.noise_amplitude > 0)
      geom::add_normal_noise(*mesh, settings_.mesh.noise_amplitude, run.seed);
    const auto& quality = mesh->quality();
    report.metric("vertices", mesh->global_count());
    report.metric("triangles", mesh->global_triangle_count());
    // Where the surface is open, both bases keep the natural (no-flux) boundary condition.
    report.metric("boundary_edges", geom::boundary_edge_count(*mesh));
    report.metric("crease_edges", geom::crease_edge_count(*mesh)); // mesh.crease_angle's
    report.metric(
        "partition",
        {{"method", settings_.partition == geom::PartitionMethod::kMorton ? "morton" : "scotch"},
         {"edge_cut", quality.edge_cut},
         {"imbalance", quality.imbalance},
         {"ghosts_max", quality.ghosts_max},
         {"halo_max", quality.halo_max},
         {"root_s", mesh->root_seconds()}});
    log::info(log::cat("mesh: ", mesh->global_count(), " vertices, ", mesh->global_triangle_count(),
                       " triangles; partition edge cut ", quality.edge_cut, ", imbalance ",
                       quality.imbalance, ", halo ", quality.halo_max, " vertices on the largest"));
  }

  const SurfaceMeasures initial_surface = measure(*mesh);
  std::unique_ptr<ReactionDiffusionSolver> solver_owner;
  std::unique_ptr<GeometrySmoother> smoother;
  GeometryState geometry{mesh->mesh().positions, mesh->mesh().positions};
  std::vector<double> initial_mass;
  // A forced model's locked phases (Fig. 5's pattern classes), summed over the run's last
  // response periods and kept in checkpoints.
  std::unique_ptr<LockedPhase> locked_phase;
  std::vector<ExtraColumn> extra_columns;
  io::CheckpointStore store(comm, run.output_dir / "checkpoints", run.config_hash,
                            run.checkpoint_keep);
  std::int64_t start = 0;
  const auto pvd_path = run.output_dir / "fem_rd.pvd";
  std::unique_ptr<io::PvdSeries> series;
  {
    auto stage = ctx.timers.scope("setup");
    if (settings_.diffusion && !settings_.diffusion->mesh_fields.empty())
      settings_.diffusion->mesh_field_values = std::make_shared<geom::DistributedMeshFields>(
          comm, settings_.mesh, settings_.diffusion->mesh_fields);
    solver_owner = std::make_unique<ReactionDiffusionSolver>(comm, *mesh, *model_, settings_.rd,
                                                             settings_.diffusion);
    if (settings_.smoothing)
      smoother = std::make_unique<GeometrySmoother>(comm, *mesh, settings_.smoother);
    for (std::size_t s = 0; s < solver_owner->species_count(); ++s)
      initial_mass.push_back(solver_owner->integral(s));
    if (model_->forcing_omega() > 0) {
      locked_phase = std::make_unique<LockedPhase>(model_->forcing_omega(), settings_.rd.dt,
                                                   settings_.steps, mesh->owned_count());
      for (const auto& [dataset, owned] : locked_phase->checkpoint_columns())
        extra_columns.push_back({dataset, owned});
    }
    if (run.restart) {
      const auto reader = store.resolve_for_restart(*run.restart);
      start = load_state(reader, *mesh, *solver_owner, geometry, extra_columns);
      if (locked_phase)
        locked_phase->resume(comm, start);
      mesh->set_positions(geometry.matrix_positions);
      solver_owner->rebuild_geometry();
      mesh->set_positions(geometry.positions);
      series = std::make_unique<io::PvdSeries>(
          io::PvdSeries::resume(comm, pvd_path, double(start) * settings_.rd.dt));
      log::info(log::cat("restarted from ", reader.path().string(), " at step ", start));
    } else {
      series = std::make_unique<io::PvdSeries>(comm, pvd_path);
    }
  }
  auto& solver = *solver_owner;
  const auto write_output = [&](std::int64_t step) {
    auto stage = ctx.timers.scope("output");
    const auto frame =
        write_frame(comm, *mesh, solver, run.output_dir / "frames", io::step_name(step));
    series->add(double(step) * settings_.rd.dt,
                std::filesystem::relative(frame, run.output_dir).string());
  };
  if (start == 0)
    write_output(0);

  log::info(log::cat("fem_rd: ", settings_.steps - start, " steps of dt ", settings_.rd.dt,
                     ", species ", solver.species_count(), ", solver ",
                     solver.solver_description()));
  par::CheckpointClock clock(comm, run.checkpoint_every, run.checkpoint_minutes);
  Progress progress("fem_rd", settings_.steps, "steps");
  std::int64_t smoothing_steps = 0; // in this run (after a restart: since the restart)
  for (std::int64_t step = start; step < settings_.steps; ++step) {
    if (smooths_at(settings_, step)) {
      auto stage = ctx.timers.scope("smoothing");
      smoother->step();
      ++smoothing_steps;
      geometry.positions = mesh->mesh().positions;
      if (settings_.smooth_functions)
        for (std::size_t s = 0; s < solver.species_count(); ++s) {
          const auto local = solver.local_values(s);
          std::vector<double> owned(local.begin(), local.begin() + mesh->owned_count());
          smoother->smooth_function(owned);
          solver.set_owned_values(s, owned);
        }
    }
    if (rebuilds_at(settings_, step)) {
      auto stage = ctx.timers.scope("rebuild");
      solver.rebuild_geometry();
      geometry.matrix_positions = mesh->mesh().positions;
    }
    {
      auto stage = ctx.timers.scope("rd_step");
      solver.step(double(step) * settings_.rd.dt);
    }
    if (locked_phase) // u, the first species
      locked_phase->add(step, solver.local_values(0).first(std::size_t(mesh->owned_count())));
    const std::int64_t done = step + 1;
    if (done % run.output_every == 0 || done == settings_.steps)
      write_output(done);
    const auto decision = clock.after_step(done);
    if (decision.checkpoint) {
      auto stage = ctx.timers.scope("checkpoint");
      save_state(store, done, *mesh, solver, geometry, extra_columns);
    }
    if (decision.stop)
      throw CheckpointedStop(decision.signal_number, "after step " + std::to_string(done));
    progress.update(done);
  }
  progress.finish();

  auto finish = ctx.timers.scope("finish");
  nlohmann::json species = nlohmann::json::object();
  std::optional<DiffusionField> field;
  if (settings_.diffusion)
    field.emplace(*settings_.diffusion, solver.species_names());
  for (std::size_t s = 0; s < solver.species_count(); ++s) {
    const auto& stats = solver.solve_stats(s);
    const auto on_surface = solver.surface_values(s);
    const auto owned = std::span(on_surface).first(std::size_t(mesh->owned_count()));
    const auto regions = count_regions_above_mean(*mesh, owned);
    const auto range = par::global_range(comm, owned);
    species[solver.species_names()[s]] = {{"cg_iterations_mean", stats.mean_iterations()},
                                          {"cg_iterations_max", stats.max_iterations},
                                          {"final_residual", stats.last_residual},
                                          {"initial_integral", initial_mass[s]},
                                          {"final_integral", solver.integral(s)},
                                          {"regions_above_mean", regions.regions},
                                          {"min", range.min},
                                          {"max", range.max}};
    if (field) {
      const StripeOrientation orientation = stripe_orientation(*mesh, on_surface, *field);
      species[solver.species_names()[s]]["stripes"] = {
          {"angle_to_field_deg", orientation.angle_to_field_deg},
          {"coherence", orientation.coherence}};
    }
  }
  report.metric("species", species);
  if (locked_phase) {
    const nlohmann::json phases = locked_phase->metrics(comm);
    report.metric("locked_phase", phases);
    log::info(log::cat("locked phase at omega_f / 4: R1 ", phases["order_1"].get<double>(), ", R2 ",
                       phases["order_2"].get<double>(), ", R4 ", phases["order_4"].get<double>(),
                       ": ", phases["phases"].get<int>(), " phase(s)"));
  }
  report.metric("steps", settings_.steps);
  report.metric("solver", solver.solver_description());
  report.metric("linear_solver", solver.solver_metrics());
  if (smoother) {
    const SurfaceMeasures final_surface = measure(*mesh);
    report.metric("smoothing",
                  {{"area_change_relative",
                    (final_surface.area - initial_surface.area) / initial_surface.area},
                   {"normal_deviation_deg_initial", initial_surface.normal_deviation_deg},
                   {"normal_deviation_deg_final", final_surface.normal_deviation_deg},
                   {"cg_iterations_mean", smoother->solve_stats().mean_iterations()},
                   {"cg_iterations_max", smoother->solve_stats().max_iterations},
                   {"steps", smoothing_steps}});
  }
  report.output(pvd_path.string());
}

} // namespace texsim::pipelines::fem_rd
