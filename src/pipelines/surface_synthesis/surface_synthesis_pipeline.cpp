#include "pipelines/surface_synthesis/surface_synthesis_pipeline.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/peak_memory.hpp"
#include "core/progress.hpp"
#include "core/stop_signal.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_source.hpp"
#include "geom/point_expression.hpp"
#include "geom/surface_field_sampler.hpp"
#include "io/checkpoint_store.hpp"
#include "par/checkpoint_clock.hpp"
#include "par/collective.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"
#include "pipelines/surface_synthesis/exemplar_pyramid.hpp"
#include "pipelines/surface_synthesis/level_frames.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"
#include "pipelines/surface_synthesis/orientation_field.hpp"
#include "pipelines/surface_synthesis/orientation_relaxation.hpp"
#include "pipelines/surface_synthesis/parent_faces.hpp"
#include "pipelines/surface_synthesis/pyramid_synthesis.hpp"
#include "pipelines/surface_synthesis/run_star.hpp"
#include "pipelines/surface_synthesis/surface_outputs.hpp"
#include "pipelines/surface_synthesis/synthesis_checkpoint.hpp"

#include <mpi.h>

#include <numeric>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// The orientation field of mode `field` at `positions` (a level's vertices): the three
/// expressions of x, y, z and the mesh arrays (sampled at the closest point of the input file's
/// surface).
std::vector<geom::Vec3> field_vectors(const OrientationSettings& settings,
                                      const geom::MeshSource& mesh_source,
                                      std::span<const geom::Vec3> positions) {
  std::vector<double> xyz;
  for (const auto& p : positions)
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  std::vector<std::vector<double>> arrays;
  if (!settings.mesh_fields.empty()) {
    auto file = geom::read_vertex_fields(mesh_source.file, settings.mesh_fields);
    for (auto& position : file.mesh.positions)
      position *= mesh_source.scale;
    const geom::SurfaceFieldSampler sampler(file.mesh, std::move(file.values));
    for (std::size_t k = 0; k < settings.mesh_fields.size(); ++k)
      arrays.push_back(sampler.sample(k, positions));
  }
  const std::vector<std::span<const double>> columns(arrays.begin(), arrays.end());
  std::vector<geom::Vec3> field(positions.size(), geom::Vec3::Zero());
  for (int c = 0; c < 3; ++c) {
    const auto values = geom::PointExpression(settings.field[std::size_t(c)], settings.mesh_fields,
                                              "surface_synthesis.orientation.field")
                            .evaluate(xyz, columns);
    for (std::size_t v = 0; v < values.size(); ++v)
      field[v][c] = values[v];
  }
  return field;
}

} // namespace

void SurfaceSynthesisPipeline::configure(const ConfigSection& section, const RunSettings& run) {
  settings_ = read_surface_synthesis_settings(section);
  seed_ = run.seed;
}

MemoryEstimate SurfaceSynthesisPipeline::estimate_memory(int ranks) const {
  auto estimate =
      geom::estimate_mesh_memory(settings_.mesh, "surface_synthesis.mesh", ranks, 400, 1000);
  // Pyramid (4/3 of the finest level), about 400 bytes a vertex over the ranks (its triangles
  // split, the runs' positions, normals, directions and colours) and the finest level gathered
  // on rank 0 for the surface outputs; stencils of the owned vertices, 2 x 49 samples x 40 bytes.
  const auto pyramid = std::uint64_t(settings_.vertices) * 4 / 3 * 400 / std::uint64_t(ranks) +
                       std::uint64_t(settings_.vertices) * 48;
  const auto stencils = std::uint64_t(settings_.vertices) * 2 * 49 * 40 / std::uint64_t(ranks);
  return larger(estimate, {pyramid + stencils + estimate.bytes, "surface_synthesis.vertices",
                           log::cat(settings_.vertices, " retiled vertices on ", settings_.levels,
                                    " levels")});
}

void SurfaceSynthesisPipeline::run(RunContext& ctx) {
  const auto& comm = ctx.comm;
  const auto& run = ctx.settings;
  auto& report = ctx.report;
  const int levels = settings_.levels;

  // The input surface M_s is rank 0's alone: it builds the mesh pyramid's levels from it and
  // carries the result back onto it (surface outputs); the other ranks work on the levels.
  geom::TriangleMesh surface;
  {
    auto stage = ctx.timers.scope("mesh");
    geom::MeshBuildReport built;
    par::run_collectively(comm, [&] {
      if (comm.is_root())
        surface = geom::build_mesh(settings_.mesh, run.seed, &built);
    });
    if (comm.is_root()) // the summary and the log are rank 0's
      geom::record_mesh_build(built, report);
  }

  std::vector<img::RgbImage> exemplar;
  {
    auto stage = ctx.timers.scope("exemplar");
    par::run_collectively(comm, [&] {
      exemplar = exemplar_pyramid(load_exemplar(settings_.exemplar, run.seed), levels,
                                  settings_.exemplar.border);
    });
    log::info(log::cat("exemplar: ", exemplar[0].width(), " x ", exemplar[0].height(), ", ", levels,
                       " levels"));
  }

  std::vector<RetiledLevel> pyramid;
  {
    auto stage = ctx.timers.scope("hierarchy");
    MeshPyramidSettings pyramid_settings;
    pyramid_settings.finest_count = settings_.vertices;
    pyramid_settings.levels = levels;
    pyramid_settings.cells = settings_.cells;
    pyramid = build_mesh_pyramid(comm, surface, run.seed, pyramid_settings);
    nlohmann::json level_metrics = nlohmann::json::array();
    for (std::size_t k = 0; k < pyramid.size(); ++k) {
      level_metrics.push_back({{"vertices", pyramid[k].vertex_count()},
                               {"triangles", pyramid[k].triangle_count()},
                               {"spacing", pyramid[k].spacing}});
    }
    report.metric("levels", level_metrics);
  }

  // Parent faces (level k on level k + 1) and orientation, coarse to fine.
  std::vector<std::vector<ParentFace>> parents(static_cast<std::size_t>(levels));
  std::vector<std::vector<geom::Vec3>> directions(static_cast<std::size_t>(levels));
  {
    auto stage = ctx.timers.scope("orientation");
    const auto& orientation = settings_.orientation;
    nlohmann::json relax_metrics = nlohmann::json::array();
    for (int k = levels - 1; k >= 0; --k) {
      const auto& level = pyramid[std::size_t(k)];
      const std::int64_t first = level.rank_offsets[std::size_t(comm.rank)];
      const auto& normals = level.normals; // this rank's run
      if (k + 1 < levels)                  // each rank searches and keeps its own run
        parents[std::size_t(k)] = find_parent_faces(comm, level, pyramid[std::size_t(k) + 1]);
      auto& s = directions[std::size_t(k)]; // this rank's run
      const auto random = random_directions(normals, run.seed, k, first);
      if (orientation.mode == OrientationMode::random) {
        s = random;
      } else if (orientation.mode == OrientationMode::field) {
        // Rank 0 gathers the level's positions, reads the mesh arrays and evaluates the field;
        // each rank gets its run.
        std::vector<std::vector<std::array<double, 3>>> runs(std::size_t(comm.size));
        const auto positions = gather_level_positions(comm, level);
        par::run_collectively(comm, [&] {
          if (!comm.is_root())
            return;
          const auto field = field_vectors(orientation, settings_.mesh, positions);
          for (std::size_t v = 0; v < field.size(); ++v)
            runs[std::size_t(par::owner_of(level.rank_offsets, std::int64_t(v)))].push_back(
                {field[v].x(), field[v].y(), field[v].z()});
        });
        std::vector<geom::Vec3> field;
        for (const auto& f : par::exchange_records(comm, std::move(runs)))
          field.emplace_back(f[0], f[1], f[2]);
        std::int64_t degenerate = 0;
        s = projected_directions(normals, field, &degenerate);
        MPI_Allreduce(MPI_IN_PLACE, &degenerate, 1, MPI_INT64_T, MPI_SUM, comm.raw);
        if (degenerate > 0)
          log::info(log::cat("level ", k,
                             ": the orientation field is normal to the surface or "
                             "zero at ",
                             degenerate, " vertices (they take a fallback direction)"));
      } else {
        std::optional<CoarserOrientation> coarser;
        if (k + 1 < levels) {
          const auto& coarse = pyramid[std::size_t(k) + 1];
          coarser = coarser_orientation(comm, parents[std::size_t(k)], coarse.rank_offsets,
                                        directions[std::size_t(k) + 1], coarse.normals);
          s = inherited_directions(normals, *coarser, orientation.symmetry, random);
        } else {
          s = random;
        }
        const auto relaxed = relax_directions(comm, level.rank_offsets, run_rings(level, comm.rank),
                                              normals, coarser ? &*coarser : nullptr,
                                              orientation.symmetry, orientation.sweeps, s);
        relax_metrics.push_back({{"level", k},
                                 {"energy_start", relaxed.energy.front()},
                                 {"energy_end", relaxed.energy.back()},
                                 {"colour_classes", relaxed.colour_classes}});
        log::info(log::cat("level ", k, ": orientation relaxed in ", orientation.sweeps,
                           " sweeps, energy ", relaxed.energy.front(), " -> ",
                           relaxed.energy.back()));
      }
    }
    if (!relax_metrics.empty())
      report.metric("relaxation", relax_metrics);
  }

  const SynthesisIdentity identity{exemplar_hash(exemplar), hierarchy_hash(pyramid)};
  io::CheckpointStore store(comm, run.output_dir / "checkpoints", run.config_hash,
                            run.checkpoint_keep);
  std::vector<LevelColours> colours;
  std::optional<SynthesisPosition> resumed;
  std::int64_t classes_done = 0;
  if (run.restart) {
    const auto reader = store.resolve_for_restart(*run.restart);
    par::run_collectively(
        comm, [&] { resumed = load_synthesis(comm, reader, pyramid, identity, colours); });
    classes_done = reader.step();
    log::info(log::cat("restarted from ", reader.path().string(), " at level ", resumed->level,
                       ", pass ", int(resumed->pass), ", class ", resumed->next_class));
  } else {
    colours = random_start(pyramid, exemplar, run.seed, comm.rank);
  }
  LevelFrames frames(
      comm, run.output_dir,
      resumed
          ? std::optional<double>(LevelFrames::time_of(levels, resumed->level, resumed->pass) - 0.5)
          : std::nullopt);

  par::CheckpointClock clock(comm, run.checkpoint_every, run.checkpoint_minutes);
  Progress progress("surface_synthesis", 2 * levels, "passes");
  PyramidSynthesisHooks hooks;
  hooks.after_class = [&](int k, Pass pass, std::int32_t c, std::int32_t classes) {
    const auto decision = clock.after_step(++classes_done);
    if (decision.checkpoint) {
      auto timer = ctx.timers.scope("checkpoint");
      save_synthesis(comm, store, classes_done, pyramid, colours, {k, pass, c + 1}, identity);
    }
    if (decision.stop)
      throw CheckpointedStop(
          decision.signal_number,
          log::cat("at level ", k, ", pass ", int(pass), " after class ", c + 1, " of ", classes));
  };
  hooks.after_pass = [&](int k, Pass pass) {
    auto timer = ctx.timers.scope("output");
    frames.write(levels, k, pass, pyramid[std::size_t(k)], directions[std::size_t(k)],
                 colours[std::size_t(k)]);
    progress.update(2 * (levels - 1 - k) + int(pass));
  };
  PyramidSynthesisInput input{pyramid, directions, parents, exemplar};
  for (int k = 0; k < levels; ++k)
    input.shapes.push_back(settings_.shape(k));
  input.method = settings_.search;
  input.border = settings_.exemplar.border;
  input.seed = run.seed;
  const auto synthesis = synthesize_pyramid(comm, input, colours, resumed, hooks, ctx.timers);
  progress.finish();

  nlohmann::json level_reports = nlohmann::json::array();
  double uncovered = 0;
  int collapsed_from = -1;
  for (const auto& level : synthesis.levels) {
    level_reports.push_back({{"level", level.level},
                             {"classes_pass1", level.classes[0]},
                             {"classes_pass2", level.classes[1]},
                             {"uncovered_fraction", level.uncovered_fraction},
                             {"distinct_colours", level.distinct_colours}});
    // The coarsest level of the run of one-colour levels that ends at the finest, if any.
    if (level.distinct_colours != 1)
      collapsed_from = -1;
    else if (collapsed_from < 0)
      collapsed_from = level.level;
    if (level.level == 0)
      uncovered = level.uncovered_fraction;
  }
  if (collapsed_from >= 0)
    log::warn(log::cat("surface_synthesis: the result is one colour everywhere, from level ",
                       collapsed_from,
                       " on: the exemplar's features are too wide for the neighbourhoods or "
                       "averaged away on its coarse levels; use fewer `surface_synthesis.levels`, "
                       "larger `surface_synthesis.neighbourhoods` or an exemplar with smaller "
                       "features"));
  const double final_error = synthesis.neighbourhood_error;
  const double random_error = synthesis.random_start_error;
  nlohmann::json quality = {{"neighbourhood_error", final_error},
                            {"uncovered_fraction", uncovered}};
  if (!resumed)
    quality["neighbourhood_error_random_start"] = random_error;
  {
    auto stage = ctx.timers.scope("atlas");
    const auto written = write_surface_outputs(comm, surface, pyramid.front(), colours.front(),
                                               exemplar.front(), settings_, run.output_dir);
    quality["histogram_distance"] = written.histogram_distance;
    for (const auto& path : written.files)
      report.output(path.string());
  }
  report.metric("quality", quality);
  report.metric("synthesis_levels", level_reports);
  std::int64_t peak = peak_resident_bytes();
  MPI_Allreduce(MPI_IN_PLACE, &peak, 1, MPI_INT64_T, MPI_MAX, comm.raw);
  report.metric("memory", {{"peak_resident_bytes_max_rank", peak},
                           {"search_bytes_max_level", std::int64_t(synthesis.search_bytes)},
                           {"halo_vertices_max_rank", synthesis.halo_vertices}});
  report.output(frames.path().string());
  log::info(log::cat("neighbourhood error ", final_error,
                     resumed ? std::string() : log::cat(" (random start ", random_error, ")"),
                     ", uncovered samples ", uncovered));
}

} // namespace texsim::pipelines::surface_synthesis
