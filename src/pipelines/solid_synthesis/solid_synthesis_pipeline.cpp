#include "pipelines/solid_synthesis/solid_synthesis_pipeline.hpp"

#include "core/log.hpp"
#include "core/progress.hpp"
#include "core/stop_signal.hpp"
#include "io/checkpoint_store.hpp"
#include "par/checkpoint_clock.hpp"
#include "par/collective.hpp"
#include "pipelines/solid_synthesis/appearance_space_cache.hpp"
#include "pipelines/solid_synthesis/level_checkpoint.hpp"
#include "pipelines/solid_synthesis/result_quality.hpp"
#include "pipelines/solid_synthesis/similarity_set_cache.hpp"
#include "pipelines/solid_synthesis/synthesis_coherence.hpp"
#include "pipelines/solid_synthesis/synthesis_exemplar.hpp"
#include "pipelines/solid_synthesis/synthesis_result.hpp"

#include <algorithm>
#include <memory>
#include <optional>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Samples per axis the neighbourhood-error metric aims for when no stride is configured.
constexpr int kMetricSamplesPerAxis = 16;

/// The similarity sets of one stack level: from the cache when it holds them for exactly these
/// features and options, else computed and stored there.
SimilaritySets obtain_similarity_sets(const par::Comm& comm, const vol::ChannelGrid& features,
                                      const SimilarityOptions& options,
                                      const std::filesystem::path& cache_dir, bool& from_cache) {
  const std::string key = similarity_cache_key(features, options);
  const auto file = cache_dir / ("similarity_sets_" + key + ".h5");
  if (!cache_dir.empty())
    if (auto cached = load_similarity_sets(comm, file, key)) {
      from_cache = true;
      return std::move(*cached);
    }
  from_cache = false;
  SimilaritySets sets = build_similarity_sets(comm, features, options);
  if (!cache_dir.empty())
    save_similarity_sets(comm, file, key, sets);
  return sets;
}

/// A level's report, with the work of the busiest rank (voxels it computes; a replicated level is
/// computed whole on every rank) and the halo bytes a rank sends per exchange. Collective.
nlohmann::json level_json(const par::Comm& comm, const LevelStats& stats,
                          const LevelLayout& layout) {
  const std::int64_t plane = std::int64_t{layout.size} * layout.size;
  std::int64_t owned = (layout.z_end - layout.z_begin) * plane;
  MPI_Allreduce(MPI_IN_PLACE, &owned, 1, MPI_INT64_T, MPI_MAX, comm.raw);
  const bool split = !layout.replicated;
  return {{"level", stats.level},
          {"spacing", stats.spacing},
          {"stack_level", stats.stack_level},
          {"corrected", stats.corrected},
          {"mean_match_distance", stats.mean_match_distance},
          {"replicated", layout.replicated && comm.size > 1},
          {"voxels_max_rank", owned},
          {"halo_exchanges", stats.halo_exchanges},
          {"passes", stats.passes},
          {"pass_mean_match_distances", stats.pass_distances},
          {"ranks_computing", layout.replicated ? comm.size : layout.ranks},
          {"halo_bytes_per_exchange",
           split ? 2 * kSlabHalo * plane * std::int64_t{sizeof(Position)} : 0}};
}

} // namespace

void SolidSynthesisPipeline::configure(const ConfigSection& section, const RunSettings&) {
  settings_ = read_solid_synthesis_settings(section);
}

void SolidSynthesisPipeline::run(RunContext& ctx) {
  const auto& comm = ctx.comm;
  const auto& run = ctx.settings;
  auto& report = ctx.report;

  Exemplar exemplar;
  AppearanceSpace space;
  {
    auto stage = ctx.timers.scope("exemplar");
    exemplar = load_exemplar_once_per_node(comm, settings_.exemplar);
    require_exemplar_fits_window(exemplar, settings_.exemplar, settings_.appearance.window);
    const auto dims = exemplar.colours.dims();
    log::info(log::cat("exemplar: ", exemplar.description, ", ", dims.nx, " x ", dims.ny, " x ",
                       dims.nz, " x ", exemplar.colours.channels(), " channels"));
  }
  {
    auto stage = ctx.timers.scope("features");
    // The transformed exemplar is computed once per exemplar and options, then reused (3.1).
    const std::string key = appearance_cache_key(exemplar.content_hash, settings_.appearance);
    const auto cache_file = settings_.cache_dir / ("appearance_" + key + ".h5");
    std::optional<AppearanceSpace> cached;
    if (!settings_.cache_dir.empty())
      cached = load_appearance_space(comm, cache_file, key);
    const bool from_cache = cached.has_value();
    if (from_cache) {
      space = std::move(*cached);
    } else {
      par::run_collectively(comm, [&] {
        space = build_appearance_space(comm, exemplar.colours, settings_.appearance);
      });
      if (!settings_.cache_dir.empty())
        save_appearance_space(comm, cache_file, key, space);
    }
    // The Gaussian stack was for the features and the cache; synthesis reads the features, the
    // outputs space.colours, so the stack and the loaded exemplar's colours (both once per node)
    // go (its hash and description stay).
    space.stack.clear();
    exemplar.colours = vol::ChannelGrid();
    log::info(log::cat("appearance space: ", from_cache ? "read from the cache" : "computed"));
    nlohmann::json retained = nlohmann::json::array();
    for (const auto& level : space.levels)
      retained.push_back(level.retained_variance);
    const auto dims = space.colours.dims();
    report.metric("exemplar", {{"description", exemplar.description},
                               {"dims", {dims.nx, dims.ny, dims.nz}},
                               {"channels", space.colours.channels()},
                               {"stack_levels", space.levels.size()},
                               {"pca_retained_variance", retained},
                               {"features", from_cache ? "cache" : "computed"}});
  }

  const int pyramid_levels = settings_.synthesis.levels;
  std::vector<SimilaritySets> sets(space.levels.size());
  {
    auto stage = ctx.timers.scope("similarity_sets");
    nlohmann::json cache_use = nlohmann::json::object();
    for (const int s : corrected_stack_levels(space, pyramid_levels)) {
      bool from_cache = false;
      sets[s] = obtain_similarity_sets(comm, space.levels[s].features, settings_.similarity,
                                       settings_.cache_dir, from_cache);
      cache_use[std::to_string(s)] = from_cache ? "cache" : "computed";
      log::info(log::cat("similarity sets, stack level ", s, ": ",
                         from_cache ? "read from the cache" : "computed"));
    }
    report.metric("similarity_sets", {{"k", settings_.similarity.k},
                                      {"window", settings_.similarity.window},
                                      {"levels", cache_use}});
  }
  if (settings_.mode == RunMode::similarity_sets)
    return;

  std::unique_ptr<AxesField> field;
  if (settings_.field)
    par::run_collectively(comm, [&] { field = make_axes_field(*settings_.field); });
  SynthesisOptions options = settings_.synthesis;
  options.seed = run.seed;
  std::optional<PyramidSynthesizer> synthesizer;
  synthesizer.emplace(comm, make_synthesis_exemplar(space, sets), options, field.get());

  io::CheckpointStore store(comm, run.output_dir / "checkpoints", run.config_hash,
                            run.checkpoint_keep);
  std::unique_ptr<CoordinateSlab> slab;
  nlohmann::json levels = nlohmann::json::array();
  {
    auto stage = ctx.timers.scope("synthesis");
    if (run.restart) {
      const auto reader = store.resolve_for_restart(*run.restart);
      slab = std::make_unique<CoordinateSlab>(load_level(comm, reader, exemplar.content_hash));
      log::info(
          log::cat("restarted from ", reader.path().string(), " after level ", level_of(*slab)));
    }
    par::CheckpointClock clock(comm, run.checkpoint_every, run.checkpoint_minutes);
    int stop_signal = 0;
    const auto stop_requested = [&] { return (stop_signal = clock.agreed_stop_signal()) != 0; };
    Progress progress("solid_synthesis", pyramid_levels + 1, "levels");
    for (int level = slab ? level_of(*slab) + 1 : 0; level <= pyramid_levels; ++level) {
      LevelStats stats;
      if (level == 0) {
        slab = std::make_unique<CoordinateSlab>(synthesizer->first_level(stats));
      } else {
        auto next = synthesizer->next_level(*slab, stats, stop_requested);
        if (!next) {
          // Stopped inside a level: the finished level before it is what a restart needs.
          auto checkpoint = ctx.timers.scope("checkpoint");
          save_level(comm, store, *slab, exemplar.content_hash);
          throw CheckpointedStop(stop_signal,
                                 log::cat("after level ", level - 1, " (level ", level,
                                          " was stopped between correction subpasses)"));
        }
        slab = std::make_unique<CoordinateSlab>(std::move(*next));
      }
      levels.push_back(level_json(comm, stats, slab->layout()));
      log::info(log::cat(
          "level ", level, ": ", slab->size(), "^3 voxels, spacing ", stats.spacing,
          slab->layout().replicated && comm.size > 1 ? ", replicated (too small to split)"
          : slab->layout().ranks < comm.size
              ? log::cat(", split over ", slab->layout().ranks, " ranks, the others waiting")
              : std::string(),
          stats.corrected ? ", corrected" : ", not corrected",
          stats.corrected ? log::cat(", ", stats.passes, stats.passes == 1 ? " pass" : " passes",
                                     ", mean match distance ", stats.mean_match_distance)
                          : std::string()));
      const auto decision = clock.after_step(level);
      if (decision.checkpoint || (run.checkpoint_every > 0 && level == pyramid_levels)) {
        auto checkpoint = ctx.timers.scope("checkpoint");
        save_level(comm, store, *slab, exemplar.content_hash);
      }
      if (decision.stop)
        throw CheckpointedStop(decision.signal_number, log::cat("after level ", level));
      progress.update(level + 1);
    }
    progress.finish();
  }
  report.metric("levels", levels);

  // The outputs read the exemplar colours and the finest features only.
  synthesizer.reset();
  sets.clear();
  space.levels.resize(1);
  {
    auto stage = ctx.timers.scope("output");
    slab->exchange_halo(comm); // the pieces share each next slab's first plane
    std::optional<LevelJacobians> finest_jacobians;
    if (field) // with the halo planes the metrics read through
      finest_jacobians = sample_level(*field, slab->size(), slab->layout().z_begin - kSlabHalo,
                                      slab->layout().z_end + kSlabHalo, slab->size());
    const double incoherent =
        incoherent_fraction(comm, *slab, finest_jacobians ? &*finest_jacobians : nullptr,
                            space.colours.dims(), settings_.dims);
    for (const auto& path :
         write_parallel_result(comm, run.output_dir, *slab, settings_.dims, space.colours))
      report.output(path.string());
    const int largest = *std::max_element(settings_.dims.begin(), settings_.dims.end());
    const int stride = settings_.metric_stride > 0 ? settings_.metric_stride
                                                   : std::max(1, largest / kMetricSamplesPerAxis);
    const double error =
        slab_neighbourhood_error(comm, *slab, finest_jacobians ? &*finest_jacobians : nullptr,
                                 settings_.dims, space.levels.front(), space.colours, stride);
    const double histogram = slab_histogram_distance(comm, *slab, settings_.dims, space.colours);
    nlohmann::json quality = {{"neighbourhood_error", error},
                              {"neighbourhood_error_stride", stride},
                              {"histogram_distance", histogram},
                              {"incoherent_fraction", incoherent}};
    // A copy warped by a varying field has no constant offset: isometric and uniform fields only.
    const std::optional<Eigen::Matrix3f> uniform =
        finest_jacobians ? uniform_jacobian(comm, *finest_jacobians)
                         : std::optional(Eigen::Matrix3f(Eigen::Matrix3f::Identity()));
    quality["largest_offset_share"] =
        uniform ? nlohmann::json(largest_offset_share(comm, *slab, &*uniform, space.colours.dims(),
                                                      settings_.dims))
                : nlohmann::json();
    report.metric("quality", quality);
    log::info(log::cat("quality: neighbourhood error ", error, ", histogram distance ", histogram,
                       ", incoherent voxels ", incoherent));
  }
  space.levels.clear(); // before the ranks hold their coloured planes
  // The output's stages are timed apart for the scaling model (scripts/bench scale).
  for (const auto& path :
       write_volume_and_sections(comm, run.output_dir, *slab, settings_.dims, space.colours,
                                 settings_.cross_sections, settings_.vdb_compression, ctx.timers))
    report.output(path.string());
  report.metric("cross_section_sets", static_cast<int>(settings_.cross_sections.size()) + 1);
  report.metric("result_dims", {settings_.dims[0], settings_.dims[1], settings_.dims[2]});
}

} // namespace texsim::pipelines::solid_synthesis
