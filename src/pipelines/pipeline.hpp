#pragma once
/// The interface every pipeline implements, and the settings all of them share.
///
/// Life cycle (driven by app/): configure() on every rank with the same broadcast config, then
/// run() on every rank. configure() only reads and validates (no files written, no heavy work), so
/// `texsim validate` calls it alone.
#include "core/config.hpp"
#include "core/memory_budget.hpp"
#include "core/run_report.hpp"
#include "core/stage_timers.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace texsim::pipelines {

/// Keys every config has besides the pipeline's own section (read by app/run_settings.cpp). The
/// initial values are the keys' defaults (README's table), here and nowhere else.
struct RunSettings {
  std::filesystem::path output_dir; ///< output.dir: everything the run writes goes here
  int output_every = 10;            ///< output.every: steps between ParaView frames
  int checkpoint_every = 0;         ///< checkpoint.every: steps between checkpoints (0 = never)
  int checkpoint_keep = 3;          ///< checkpoint.keep: how many recent checkpoints to keep
  /// checkpoint.minutes: wall time between checkpoints (0 = never); unset: 30 on several nodes,
  /// 60 on one (par::default_checkpoint_minutes)
  std::optional<double> checkpoint_minutes;
  std::uint64_t seed = 1;             ///< seed: key of every counter-based random stream
  std::optional<std::string> restart; ///< --restart: "latest" or a checkpoint path
  std::string config_hash;            ///< ConfigDocument::result_hash(), stored in checkpoints
};

/// What run() gets: communicator, settings, and where to record timings, metrics and outputs.
struct RunContext {
  par::Comm comm;
  const RunSettings& settings;
  StageTimers& timers;
  RunReport& report;
};

class Pipeline {
public:
  virtual ~Pipeline() = default;

  /// Reads and validates the pipeline's own section (the YAML key named after the pipeline);
  /// `run` holds the common settings (seed, output, ...). Throws InputError naming the key path.
  /// Called on every rank; not collective.
  virtual void configure(const ConfigSection& section, const RunSettings& run) = 0;

  /// Does the work. Collective over ctx.comm.
  virtual void run(RunContext& ctx) = 0;

  /// Config key paths that only say how long to run (e.g. "fem_rd.time.steps"): left out of the
  /// config hash, so a finished run can be continued with --restart and a larger value.
  virtual std::vector<std::string> run_length_keys() const { return {}; }

  /// Peak memory per rank at `ranks` ranks, estimated from the settings configure() read (it may
  /// read file headers), naming the key that drives it; bytes 0 when not estimated. main()
  /// refuses a run whose estimate exceeds the memory of its node. Called on every rank after
  /// configure(); not collective.
  virtual MemoryEstimate estimate_memory(int /*ranks*/) const { return {}; }

  /// False for a pipeline that writes no checkpoints: --restart is then refused.
  virtual bool restartable() const { return true; }
};

} // namespace texsim::pipelines
