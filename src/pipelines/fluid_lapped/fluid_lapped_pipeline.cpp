#include "pipelines/fluid_lapped/fluid_lapped_pipeline.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/log.hpp"
#include "core/peak_memory.hpp"
#include "core/progress.hpp"
#include "core/stop_signal.hpp"
#include "geom/mesh_source.hpp"
#include "geom/poisson_disk_points.hpp"
#include "io/checkpoint_store.hpp"
#include "par/checkpoint_clock.hpp"
#include "par/collective.hpp"
#include "pipelines/fluid_lapped/atlas_compositor.hpp"
#include "pipelines/fluid_lapped/erosion_mask.hpp"
#include "pipelines/fluid_lapped/fluid_exemplar.hpp"
#include "pipelines/fluid_lapped/frame_outputs.hpp"
#include "pipelines/fluid_lapped/frame_surface.hpp"
#include "pipelines/fluid_lapped/patch_advection.hpp"
#include "pipelines/fluid_lapped/patch_builder.hpp"
#include "pipelines/fluid_lapped/patch_distortion.hpp"
#include "pipelines/fluid_lapped/patch_exchange.hpp"
#include "pipelines/fluid_lapped/patch_population.hpp"
#include "pipelines/fluid_lapped/prepared_frames.hpp"

#include <mpi.h>

#include <map>

namespace texsim::pipelines::fluid_lapped {
namespace {

/// The frames and the flow between them: simulator files, or one surface and an analytic flow.
class Animation {
public:
  Animation(const par::Comm& comm, const FluidLappedSettings& settings, std::uint64_t seed)
      : settings_(settings) {
    const auto& frames = settings.frames;
    if (frames.files) {
      par::run_collectively(comm, [&] { source_.emplace(*frames.files); });
      count_ = frames.count > 0 ? std::min(frames.count, source_->frame_count())
                                : source_->frame_count();
      if (frames.count > source_->frame_count())
        log::warn(log::cat("fluid_lapped.frames.count is ", frames.count, " but the files hold ",
                           source_->frame_count(), " frames; running those"));
    } else {
      par::run_collectively(comm, [&] {
        static_frame_.time = 0;
        static_frame_.mesh = geom::build_mesh(frames.mesh, seed);
        flow_ = make_analytic_flow(frames.flow);
      });
      count_ = frames.count;
    }
    prepared_.emplace(
        comm, count_, [this](int k) { return read(k); }, settings.atlas);
  }

  int count() const { return count_; }
  double time(int k) const { return source_ ? source_->time(k) : k * settings_.frames.interval; }
  bool is_static() const { return !source_; }

  /// Frame k, prepared (collective, increasing k). A fixed surface is prepared once.
  const PreparedFrame& frame(int k) {
    if (!current_ || !is_static()) {
      previous_ = std::move(current_);
      current_ = prepared_->get(k);
    }
    return *current_;
  }

  /// The velocity from frame k - 1 to frame k (after frame(k - 1) and frame(k)): the frames'
  /// velocity grids or their surfaces' point arrays. Collective (errors reach every rank).
  std::unique_ptr<VelocityField> velocity(const par::Comm& comm, int k) const {
    if (flow_)
      return nullptr;
    std::unique_ptr<VelocityField> velocity;
    par::run_collectively(comm, [&] {
      if (source_->has_velocity_grids()) {
        velocity = make_grid_velocity(source_->velocity_grid(k - 1), time(k - 1),
                                      source_->velocity_grid(k), time(k));
      } else {
        TEXSIM_VERIFY(previous_, "no previous frame for the velocity");
        velocity = make_surface_velocity(previous_->frame, current_->frame);
      }
    });
    return velocity;
  }
  const VelocityField* analytic_flow() const { return flow_.get(); }

  /// What the frames were read from, for checkpoints (the config covers analytic flows).
  std::string inputs_hash() const {
    std::string text;
    if (source_)
      for (int k = 0; k < source_->frame_count(); ++k)
        text += log::cat(source_->time(k), ";");
    return text;
  }

private:
  FluidFrame read(int k) const {
    if (source_)
      return source_->read(k);
    auto frame = static_frame_;
    frame.time = time(k);
    return frame;
  }

  const FluidLappedSettings& settings_;
  std::optional<FrameSource> source_;
  FluidFrame static_frame_;
  std::unique_ptr<VelocityField> flow_;
  int count_ = 0;
  std::optional<PreparedFrames> prepared_;
  std::optional<PreparedFrame> previous_, current_;
};

/// Frame 0's patches: Poisson-disk centres (section 4), patch i built by rank i mod size.
void seed_patches(const par::Comm& comm, const FrameSurface& surface,
                  const FluidLappedSettings& settings, std::uint64_t seed, PatchState& state) {
  const auto centres = geom::poisson_disk_points(surface.mesh, settings.radius, seed);
  par::run_collectively(comm, [&] {
    for (std::size_t i = std::size_t(comm.rank); i < centres.size(); i += std::size_t(comm.size)) {
      auto patch = build_patch(surface, centres[i], settings.radius, std::int64_t(i), 0, seed, i);
      update_weights(patch, settings.radius, settings.delta_max);
      state.patches.push_back(std::move(patch));
    }
  });
  state.next_id = std::int64_t(centres.size());
  log::info(log::cat("frame 0: ", centres.size(),
                     " Poisson-disk patch centres at r = ", settings.radius));
}

/// Carries this rank's patches from frame k - 1 to frame k: advection, projection onto the new
/// surface, dropping of far vertices, new weights; patches left without triangles go.
void carry_patches(const VelocityField& velocity, double t0, double t1,
                   const FrameSurface& previous, const FrameSurface& surface,
                   const FluidLappedSettings& settings, PatchState& state, StageTimers& timers) {
  AdvectionSettings advection;
  advection.max_step_length = 0.5 * previous.mean_edge_length;
  advection.substep_multiplier = settings.substep_multiplier;
  {
    auto stage = timers.scope("advection");
    for (auto& patch : state.patches)
      advect_patch(patch, velocity, t0, t1, advection);
  }
  auto stage = timers.scope("update");
  for (auto& patch : state.patches) {
    project_patch(patch, surface, settings.radius);
    update_weights(patch, settings.radius, settings.delta_max);
  }
  std::erase_if(state.patches, [](const Patch& patch) { return patch.triangles.empty(); });
}

/// Seconds spent so far in every stage, by name.
std::map<std::string, double> stage_seconds(const StageTimers& timers) {
  std::map<std::string, double> seconds;
  for (const auto& stage : timers.stages())
    seconds[stage.name] = stage.wall_s;
  return seconds;
}

} // namespace

void FluidLappedPipeline::configure(const ConfigSection& section, const RunSettings&) {
  settings_ = read_fluid_lapped_settings(section);
}

MemoryEstimate FluidLappedPipeline::estimate_memory(int ranks) const {
  const auto texels = std::uint64_t(settings_.atlas.resolution) * settings_.atlas.resolution;
  // Tiles: 16 bytes a texel spread over the ranks; the writing rank gathers them all and colours
  // them (16 + 12 bytes a texel).
  const auto bytes = texels * 16 / std::uint64_t(ranks) + texels * 28 + (std::uint64_t(256) << 20);
  return {bytes, "fluid_lapped.atlas.resolution",
          log::cat(settings_.atlas.resolution, "^2 atlas texels")};
}

void FluidLappedPipeline::run(RunContext& ctx) {
  const auto& comm = ctx.comm;
  const auto& run = ctx.settings;
  auto& report = ctx.report;

  FluidExemplar exemplar;
  {
    auto stage = ctx.timers.scope("exemplar");
    par::run_collectively(comm, [&] { exemplar = load_fluid_exemplar(settings_.exemplar); });
    log::info(log::cat("exemplar ", exemplar.colour.width(), " x ", exemplar.colour.height(),
                       exemplar.feature_is_luminance
                           ? ", feature map: its luminance (no fluid_lapped.exemplar.feature_map)"
                           : ", feature map given"));
  }
  const ErosionMask erosion(
      std::vector<float>(exemplar.feature.data().begin(), exemplar.feature.data().end()),
      exemplar.feature.width(), exemplar.feature.height(), settings_.epsilon);

  std::optional<Animation> made;
  {
    auto stage = ctx.timers.scope("frames");
    made.emplace(comm, settings_, run.seed);
  }
  Animation& animation = *made;
  const std::string inputs_hash = hex64(fnv1a64(exemplar.hash + animation.inputs_hash()));

  io::CheckpointStore store(comm, run.output_dir / "checkpoints", run.config_hash,
                            run.checkpoint_keep);
  PatchState state;
  if (run.restart) {
    const auto reader = store.resolve_for_restart(*run.restart);
    par::run_collectively(comm, [&] { state = load_patch_state(comm, reader, inputs_hash); });
    log::info(log::cat("restarted from ", reader.path().string(), " after frame ", state.frame));
  }
  const int first = state.frame + 1;
  FrameOutputs outputs(comm, run.output_dir, exemplar, erosion,
                       run.restart ? std::optional<double>(animation.time(state.frame))
                                   : std::nullopt);

  PopulationSettings population;
  population.radius = settings_.radius;
  population.delta_max = settings_.delta_max;
  population.batch = settings_.creation_batch;
  population.seed = run.seed;

  par::CheckpointClock clock(comm, run.checkpoint_every, run.checkpoint_minutes);
  Progress progress("fluid_lapped", animation.count() - first, "frames");
  nlohmann::json frame_metrics = nlohmann::json::array();
  std::optional<FrameSurface> previous_surface;
  if (first > 0 && first < animation.count()) {
    auto stage = ctx.timers.scope("frames");
    previous_surface.emplace(animation.frame(first - 1).frame.mesh);
  }
  for (int k = first; k < animation.count(); ++k) {
    const auto stages_before = stage_seconds(ctx.timers);
    std::optional<PreparedFrame> prepared;
    {
      auto stage = ctx.timers.scope("frames");
      prepared = animation.frame(k);
    }
    FrameSurface surface(prepared->frame.mesh);
    if (k == 0) {
      auto stage = ctx.timers.scope("create");
      seed_patches(comm, surface, settings_, run.seed, state);
    } else {
      const auto data_velocity = animation.velocity(comm, k);
      const VelocityField& velocity = data_velocity ? *data_velocity : *animation.analytic_flow();
      carry_patches(velocity, animation.time(k - 1), animation.time(k), *previous_surface, surface,
                    settings_, state, ctx.timers);
    }
    std::optional<AtlasCompositor> compositor;
    {
      auto stage = ctx.timers.scope("atlas");
      compositor.emplace(comm, surface, prepared->atlas, settings_.atlas.tile, erosion);
      compositor->composite(state.patches);
    }
    PopulationReport populated;
    {
      auto stage = ctx.timers.scope("create");
      populated = populate_frame(comm, surface, *compositor, state, population);
      state.frame = k;
    }
    const auto coverage = compositor->coverage();
    {
      auto stage = ctx.timers.scope("output");
      if (k % run.output_every == 0 || k + 1 == animation.count())
        outputs.write(k, animation.time(k), *prepared, *compositor, state.patches,
                      animation.analytic_flow());
    }
    {
      auto stage = ctx.timers.scope("update");
      state.patches =
          exchange_patches(comm, state.patches, morton_destinations(comm, state.patches));
    }
    nlohmann::json seconds;
    for (const auto& [name, total] : stage_seconds(ctx.timers))
      seconds[name] = total - (stages_before.contains(name) ? stages_before.at(name) : 0.0);
    frame_metrics.push_back(
        {{"frame", k},
         {"seconds", seconds},
         {"time", animation.time(k)},
         {"patches", populated.patches},
         {"created", populated.created},
         {"removed", populated.removed},
         {"creation_rounds", populated.rounds},
         {"candidates_rejected", populated.rejected},
         {"used_texels", coverage.used},
         {"covered_texels", coverage.covered},
         {"unreachable_texels", coverage.unreachable},
         {"coverage", coverage.used ? double(coverage.covered) / double(coverage.used) : 1.0}});
    log::info(log::cat("frame ", k, ": ", populated.patches, " patches (", populated.created,
                       " new, ", populated.removed, " removed), coverage ",
                       coverage.used ? double(coverage.covered) / double(coverage.used) : 1.0));
    progress.update(k + 1 - first);
    previous_surface.emplace(std::move(surface));
    const auto decision = clock.after_step(k + 1);
    if (decision.checkpoint || k + 1 == animation.count()) {
      auto stage = ctx.timers.scope("checkpoint");
      save_patch_state(comm, store, state, inputs_hash);
    }
    if (decision.stop && k + 1 < animation.count())
      throw CheckpointedStop(decision.signal_number, log::cat("after frame ", k));
  }
  progress.finish();

  report.metric("frames", frame_metrics);
  std::int64_t peak = peak_resident_bytes();
  MPI_Allreduce(MPI_IN_PLACE, &peak, 1, MPI_INT64_T, MPI_MAX, comm.raw);
  report.metric("memory", {{"peak_resident_bytes_max_rank", peak}});
  for (const auto& path : outputs.series())
    report.output(path.string());
}

} // namespace texsim::pipelines::fluid_lapped
