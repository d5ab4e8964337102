// surface_synthesis restarts through the binary: a run SIGKILLed after a checkpoint taken between
// two colour classes, resumed at 1 rank and (a copy of it) at 2 ranks, ends with the checkpoint and
// atlas.png of the run that was never killed, byte for byte; a restart with another config is
// refused with exit code 2; and 1 and 2 OpenMP threads write the same bytes.
#include "support/output_files.hpp"
#include "support/run_command.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <string>
#include <thread>

namespace {
namespace fs = std::filesystem;
using texsim::test::BackgroundCommand;
using texsim::test::differing_files;

const fs::path kSource = TEXSIM_SOURCE_DIR;
constexpr int kEvery = 5;

fs::path scratch(const std::string& name) {
  const auto dir = fs::temp_directory_path() / ("texsim_surface_restart_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// config/surface_synthesis/smoke.yaml with a checkpoint every kEvery classes, all kept.
std::string smoke_run(int ranks, const fs::path& out, const std::string& extra = "",
                      const std::string& mpirun_options = "") {
  return texsim::test::texsim_under_mpirun(ranks, mpirun_options) + " " +
         (kSource / "config/surface_synthesis/smoke.yaml").string() +
         " --quiet --set checkpoint.every=" + std::to_string(kEvery) +
         " --set checkpoint.keep=100000 --set output.dir=" + out.string() + " " + extra;
}

/// The newest checkpoint's name under `dir`.
std::string last_checkpoint(const fs::path& dir) {
  std::string last;
  for (const auto& entry : fs::directory_iterator(dir / "checkpoints"))
    if (entry.path().extension() == ".h5")
      last = std::max(last, entry.path().filename().string());
  return last;
}

TEST(SurfaceSynthesisRestart, KilledMidPassAndResumedAtOneAndTwoRanksEndsWithTheSameBytes) {
  const auto dir = scratch("kill");
  const auto whole = texsim::test::run_command(smoke_run(1, dir / "whole"), kSource);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const std::string final_checkpoint = last_checkpoint(dir / "whole");

  const fs::path killed = dir / "killed";
  {
    BackgroundCommand job(smoke_run(1, killed), kSource);
    // The third checkpoint falls inside the finest level's classes in the smoke config.
    const auto checkpoint = killed / "checkpoints/step_000000015.h5";
    while (!fs::exists(checkpoint) && !fs::exists(killed / "summary.json"))
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    job.signal_group(SIGKILL);
    ASSERT_NE(job.finish().exit_code, 0) << "the job finished before it could be killed";
  }
  ASSERT_FALSE(fs::exists(killed / "summary.json"));
  const fs::path killed_copy = dir / "killed_copy";
  fs::copy(killed, killed_copy, fs::copy_options::recursive);

  for (const auto& [ranks, out] : {std::pair{1, killed}, std::pair{2, killed_copy}}) {
    const auto restarted = texsim::test::run_command(smoke_run(ranks, out, "--restart"), kSource);
    ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
    EXPECT_EQ(differing_files(dir / "whole", out,
                              [&](const std::string& file) {
                                return file == "atlas.png" || file == "textured.obj" ||
                                       file == "checkpoints/" + final_checkpoint;
                              }),
              std::vector<std::string>{})
        << "resumed at " << ranks << " ranks";
  }
}

TEST(SurfaceSynthesisRestart, ARestartWithAnotherConfigIsRefused) {
  const auto dir = scratch("config");
  const auto first = texsim::test::run_command(smoke_run(1, dir / "run"), kSource);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto changed = texsim::test::run_command(
      smoke_run(1, dir / "run", "--restart --set surface_synthesis.vertices=1600"), kSource);
  EXPECT_EQ(changed.exit_code, 2) << changed.output;
  EXPECT_NE(changed.output.find("config"), std::string::npos) << changed.output;
}

TEST(SurfaceSynthesisRestart, OneAndTwoThreadsWriteTheSameBytes) {
  const auto dir = scratch("threads");
  for (const int threads : {1, 2}) {
    const auto run = texsim::test::run_command(
        smoke_run(1, dir / std::to_string(threads), "",
                  "--bind-to none -x OMP_NUM_THREADS=" + std::to_string(threads)),
        kSource);
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  const auto files = texsim::test::files_under(dir / "1");
  ASSERT_GE(files.size(), 10u) << "levels, surface, atlas, checkpoints";
  EXPECT_EQ(differing_files(dir / "1", dir / "2",
                            [](const std::string& file) { return file != "summary.json"; }),
            std::vector<std::string>{});
}

} // namespace
