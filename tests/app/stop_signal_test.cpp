// A scheduler's warning before the time limit, through the binary, for every pipeline with a
// long loop: SIGTERM sent at a random moment to the ranks of `mpirun -n 2 texsim ...` (as Slurm
// and PBS signal a job's tasks), or SIGUSR1 sent to mpirun (which forwards it), makes texsim
// finish its step (or correction subpass), write a checkpoint, write no summary.json and exit
// with code 3, which mpirun passes on;
// `--restart` then finishes with the same bytes as a run that was never interrupted (every frame,
// the .pvd, solid_synthesis' .vdb and the final checkpoint).
// The moment is drawn from std::random_device and printed, so a failure can be replayed with
// TEXSIM_STOP_DELAY_MS.
#include "support/output_files.hpp"
#include "support/run_command.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <random>
#include <string>
#include <thread>

namespace {
namespace fs = std::filesystem;
using texsim::test::BackgroundCommand;

const fs::path kSource = TEXSIM_SOURCE_DIR;

enum class Delivery { kSigtermToRanks, kSigusr1ToMpirun };

struct PipelineRun {
  std::string case_name;
  std::string name;     ///< the pipeline
  std::string config;   ///< relative to the source tree
  std::string settings; ///< --set options making the run last a few seconds
  std::string final_checkpoint;
  Delivery delivery = Delivery::kSigtermToRanks;
};

std::ostream& operator<<(std::ostream& out, const PipelineRun& run) {
  return out << run.case_name;
}

std::string command(const PipelineRun& run, const fs::path& out, const std::string& extra = "") {
  return texsim::test::texsim_under_mpirun(2) + " " + (kSource / run.config).string() + " " +
         run.settings + " --set output.dir=" + out.string() + " " + extra;
}

bool compared(const std::string& file) {
  return file != "summary.json" && !file.starts_with("checkpoints/");
}

int stop_delay_ms(double run_seconds) {
  if (const char* fixed = std::getenv("TEXSIM_STOP_DELAY_MS"))
    return std::atoi(fixed);
  std::random_device device;
  std::uniform_int_distribution<int> delay(0, int(run_seconds * 500)); // the first half
  return delay(device);
}

const std::string kFemRdSettings = "--set fem_rd.mesh.level=4 --set fem_rd.time.steps=150 "
                                   "--set output.every=50 --set checkpoint.every=50";

class StopSignal : public ::testing::TestWithParam<PipelineRun> {};

TEST_P(StopSignal, CheckpointsExitsWithThreeAndRestartsToTheSameBytes) {
  const PipelineRun& run = GetParam();
  const fs::path dir = fs::temp_directory_path() / ("texsim_stop_signal_" + run.case_name);
  fs::remove_all(dir);
  fs::create_directories(dir);

  // The uninterrupted run, timed from the moment it announces itself (its handlers exist) to its
  // end: the signal below lands in the first half of that span. Relative paths in the configs
  // (the similarity-set cache) land in `dir`.
  double whole_s = 0;
  {
    BackgroundCommand job(command(run, dir / "whole"), dir);
    ASSERT_TRUE(job.wait_for_output(": pipeline " + run.name + " on 2 ranks"));
    const auto announced = std::chrono::steady_clock::now();
    const auto whole = job.finish();
    whole_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - announced).count();
    ASSERT_EQ(whole.exit_code, 0) << whole.output;
  }

  const fs::path stopped = dir / "stopped";
  {
    BackgroundCommand job(command(run, stopped), dir);
    // The signal handlers exist once the run announces itself; any moment after that is valid.
    ASSERT_TRUE(job.wait_for_output(": pipeline " + run.name + " on 2 ranks"));
    const int delay_ms = stop_delay_ms(whole_s);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    const bool to_ranks = run.delivery == Delivery::kSigtermToRanks;
    if (to_ranks)
      job.signal_children(SIGTERM);
    else
      job.signal_command(SIGUSR1);
    const std::string signal_name = to_ranks ? "SIGTERM" : "SIGUSR1";
    const auto outcome = job.finish();
    ASSERT_EQ(outcome.exit_code, 3)
        << signal_name << " " << delay_ms << " ms after the start (of a run that took " << whole_s
        << " s from there)\n"
        << outcome.output;
    const auto stopped_line =
        outcome.output.find("texsim: stopped: " + signal_name + " received: checkpoint written");
    ASSERT_NE(stopped_line, std::string::npos) << outcome.output;
    std::cout << signal_name << " after " << delay_ms << " ms: "
              << outcome.output.substr(stopped_line,
                                       outcome.output.find('\n', stopped_line) - stopped_line)
              << std::endl;
  }
  EXPECT_FALSE(fs::exists(stopped / "summary.json"));
  ASSERT_TRUE(fs::exists(stopped / "checkpoints"));
  EXPECT_FALSE(fs::is_empty(stopped / "checkpoints"));

  const auto restarted = texsim::test::run_command(command(run, stopped, "--restart"), dir);
  ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
  const auto files = texsim::test::files_under(dir / "whole");
  EXPECT_GE(std::count_if(files.begin(), files.end(), compared), 2);
  EXPECT_EQ(texsim::test::differing_files(dir / "whole", stopped, compared),
            std::vector<std::string>{});
  EXPECT_TRUE(texsim::test::same_bytes(dir / "whole" / run.final_checkpoint,
                                       stopped / run.final_checkpoint))
      << run.final_checkpoint;
}

INSTANTIATE_TEST_SUITE_P(
    Pipelines, StopSignal,
    ::testing::Values(
        PipelineRun{"fem_rd", "fem_rd", "config/fem_rd/smoke.yaml", kFemRdSettings,
                    "checkpoints/step_000000150.h5"},
        PipelineRun{"fem_rd_sigusr1_to_mpirun", "fem_rd", "config/fem_rd/smoke.yaml",
                    kFemRdSettings, "checkpoints/step_000000150.h5", Delivery::kSigusr1ToMpirun},
        PipelineRun{"turk_rd", "turk_rd", "config/turk_rd/smoke.yaml",
                    "--set turk_rd.stages.spots.steps=1500 --set turk_rd.stages.inner.steps=1500 "
                    "--set output.every=500 --set checkpoint.every=1000",
                    "checkpoints/step_000003000.h5"},
        PipelineRun{"solid_synthesis", "solid_synthesis", "config/solid_synthesis/smoke.yaml",
                    "--set solid_synthesis.synthesis.size=64", "checkpoints/step_000000006.h5"}),
    [](const auto& info) { return info.param.case_name; });

} // namespace
