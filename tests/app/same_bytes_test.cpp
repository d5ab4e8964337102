// The determinism contract through the binary, on a real scan (the bunny): the same config at the
// same rank count gives the same bytes in every frame and checkpoint, at -n 2 and at -n 3 (the
// partition is part of it); and a run killed with SIGKILL after a checkpoint, then restarted,
// ends with the same bytes as the run that was never killed; one and two OpenMP threads write the
// same bytes.
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

fs::path scratch(const std::string& name) {
  const auto dir = fs::temp_directory_path() / ("texsim_same_bytes_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// config/fem_rd/bunny.yaml, shortened: `steps` steps, frames and checkpoints every 10. Run from
/// the source tree, where the config's relative mesh path points.
std::string bunny_run(int ranks, const fs::path& out, int steps, const std::string& extra = "",
                      const std::string& mpirun_options = "") {
  return texsim::test::texsim_under_mpirun(ranks, mpirun_options) + " " +
         (kSource / "config/fem_rd/bunny.yaml").string() +
         " --quiet --set fem_rd.time.steps=" + std::to_string(steps) +
         " --set output.every=10 --set checkpoint.every=10 --set checkpoint.keep=100"
         " --set output.dir=" +
         out.string() + " " + extra;
}

bool everything_but_the_summary(const std::string& file) {
  return file != "summary.json";
}

class FemRdSameBytesOnRealData : public ::testing::TestWithParam<int> {
protected:
  void SetUp() override {
    if (!fs::exists(kSource / "data/meshes/bunny00.off"))
      GTEST_SKIP() << "data/meshes/bunny00.off missing: run scripts/fetch-data";
  }
};

TEST_P(FemRdSameBytesOnRealData, TwoRunsWriteTheSameBytes) {
  const int ranks = GetParam();
  const auto dir = scratch(std::to_string(ranks) + "_ranks");
  for (const char* run : {"a", "b"}) {
    const auto outcome = texsim::test::run_command(bunny_run(ranks, dir / run, 20), kSource);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  }
  const auto files = texsim::test::files_under(dir / "a");
  ASSERT_GE(files.size(), 6u) << "frames, checkpoints, .pvd";
  EXPECT_EQ(texsim::test::files_under(dir / "b"), files);
  EXPECT_EQ(differing_files(dir / "a", dir / "b", everything_but_the_summary),
            std::vector<std::string>{});
}

INSTANTIATE_TEST_SUITE_P(Ranks, FemRdSameBytesOnRealData, ::testing::Values(2, 3));

// OpenBLAS, under PETSc's vector reductions, would split dot products by the thread count.
TEST_F(FemRdSameBytesOnRealData, OneAndTwoThreadsWriteTheSameBytes) {
  const auto dir = scratch("threads");
  for (const int threads : {1, 2}) {
    const auto outcome = texsim::test::run_command(
        bunny_run(1, dir / std::to_string(threads), 20, "",
                  "--bind-to none -x OMP_NUM_THREADS=" + std::to_string(threads)),
        kSource);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  }
  ASSERT_GE(texsim::test::files_under(dir / "1").size(), 6u) << "frames, checkpoints, .pvd";
  EXPECT_EQ(differing_files(dir / "1", dir / "2", everything_but_the_summary),
            std::vector<std::string>{});
}

TEST_F(FemRdSameBytesOnRealData, KilledAfterACheckpointAndRestartedEndsWithTheSameBytes) {
  constexpr int kSteps = 30;
  const auto dir = scratch("sigkill");
  const auto whole = texsim::test::run_command(bunny_run(2, dir / "whole", kSteps), kSource);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;

  const fs::path killed = dir / "killed";
  {
    BackgroundCommand job(bunny_run(2, killed, kSteps), kSource);
    // Kill the whole job (mpirun and its ranks) the moment the step-10 checkpoint exists.
    const auto checkpoint = killed / "checkpoints/step_000000010.h5";
    while (!fs::exists(checkpoint) && !fs::exists(killed / "summary.json"))
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    job.signal_group(SIGKILL);
    const auto outcome = job.finish();
    ASSERT_NE(outcome.exit_code, 0) << "the job finished before it could be killed";
  }
  ASSERT_FALSE(fs::exists(killed / "summary.json"));
  const auto restarted =
      texsim::test::run_command(bunny_run(2, killed, kSteps, "--restart"), kSource);
  ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
  EXPECT_EQ(differing_files(dir / "whole", killed,
                            [](const std::string& file) {
                              return file == "fem_rd.pvd" || file.starts_with("frames/") ||
                                     file == "checkpoints/step_000000030.h5";
                            }),
            std::vector<std::string>{});
}

} // namespace
