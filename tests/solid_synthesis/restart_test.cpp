// Through the binary, as a user runs it: config/solid_synthesis/smoke.yaml (16^3 marble exemplar
// to 32^3, a checkpoint after every pyramid level) gives the same bytes in its .vdb and the same
// voxels in its parallel .pvti volumes at -n 1, 2 and 3; a copy of the -n 2 run that lost the
// checkpoints after level 3 (a job killed mid-pyramid) and is continued with --restart, at -n 2
// (then with the same bytes in every piece) and at -n 3, ends with the same volumes too (also under
// a slant field, whose checkpoints hold sub-voxel positions); and the second run reads its
// appearance space and similarity sets from the cache the first one wrote. The scan kernels of
// every instruction set the CPU runs give the same bytes. The texsim runs are
// child jobs (support/run_command.hpp); this program itself runs on one rank.
#include "core/float_distance_scan.hpp"
#include "support/output_files.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"
#include "vol/vti_io.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace texsim {
namespace {
namespace fs = std::filesystem;

constexpr int kLastKeptLevel = 3;
constexpr int kFinestLevel = 5; // 32^3

test::CommandOutcome run_smoke(int ranks, const fs::path& out, const fs::path& cache,
                               const std::string& options = "") {
  return test::run_command(test::texsim_under_mpirun(ranks) + " " +
                           (test::source_dir() / "config/solid_synthesis/smoke.yaml").string() +
                           " --set output.dir=" + out.string() +
                           " --set solid_synthesis.similarity.cache_dir=" + cache.string() + " " +
                           options);
}

/// "<prefix><ranks>": a run directory name per rank count.
std::string with_ranks(std::string prefix, int ranks) {
  return prefix.append(std::to_string(ranks));
}

/// The .vdb has the same bytes at any rank count (its UUID follows its content); the parallel
/// .pvti volumes (one piece per rank, so other files at another rank count) hold the same voxels,
/// and at the same rank count every piece and .pvti has the same bytes.
void expect_same_volumes(const fs::path& a, const fs::path& b, bool same_ranks) {
  EXPECT_TRUE(test::read_text(a / "solid_synthesis.vdb") ==
              test::read_text(b / "solid_synthesis.vdb"))
      << "the .vdb differs: " << a << ", " << b;
  for (const std::string volume : {"exemplar_coordinates", "solid_synthesis"}) {
    const auto grid_a = std::get<vol::RgbGrid>(vol::read_vti(a / (volume + ".pvti")));
    const auto grid_b = std::get<vol::RgbGrid>(vol::read_vti(b / (volume + ".pvti")));
    EXPECT_EQ(grid_a.dims(), (vol::Dims{32, 32, 32}));
    EXPECT_TRUE(grid_a == grid_b) << volume << " differs between " << a << " and " << b;
    if (!same_ranks)
      continue;
    EXPECT_TRUE(test::read_text(a / (volume + ".pvti")) == test::read_text(b / (volume + ".pvti")));
    for (const auto& piece : fs::directory_iterator(a / volume))
      EXPECT_TRUE(test::read_text(piece.path()) ==
                  test::read_text(b / volume / piece.path().filename()))
          << piece.path().filename() << " differs between " << a << " and " << b;
  }
}

class SolidSynthesisRuns : public testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = test::scratch_dir("solid_synthesis_restart");
    const auto outcome = run_smoke(2, dir_ / "n2", dir_ / "cache");
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  }
  static fs::path dir_;
};
fs::path SolidSynthesisRuns::dir_;

TEST_F(SolidSynthesisRuns, NoTemporaryFileIsLeftInTheRunOrTheCache) {
  // .vdb, .pvti and pieces, slice PNGs, checkpoints, caches, summary.json: all renamed into place.
  EXPECT_TRUE(fs::exists(dir_ / "n2" / "solid_synthesis.vdb"));
  EXPECT_TRUE(test::temporary_files_under(dir_ / "n2").empty());
  EXPECT_TRUE(test::temporary_files_under(dir_ / "cache").empty());
}

TEST_F(SolidSynthesisRuns, SameBytesAtOneTwoAndThreeRanks) {
  for (const int ranks : {1, 3}) {
    const fs::path out = dir_ / with_ranks("n", ranks);
    const auto outcome = run_smoke(ranks, out, dir_ / with_ranks("cache_n", ranks));
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
    expect_same_volumes(dir_ / "n2", out, false);
  }
}

TEST_F(SolidSynthesisRuns, SameBytesWhenRanksSpanSeveralNodes) {
  // Three ranks as two nodes (TEXSIM_RANKS_PER_NODE=2): the node-shared exemplar levels travel
  // between the nodes' leaders, both when they are computed and when they come from the cache.
  const fs::path cache = dir_ / "cache_two_nodes";
  for (const char* run : {"two_nodes_computed", "two_nodes_cached"}) {
    const auto outcome =
        test::run_command(test::texsim_under_mpirun(3, "-x TEXSIM_RANKS_PER_NODE=2") + " " +
                          (test::source_dir() / "config/solid_synthesis/smoke.yaml").string() +
                          " --set output.dir=" + (dir_ / run).string() +
                          " --set solid_synthesis.similarity.cache_dir=" + cache.string());
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
    expect_same_volumes(dir_ / "n2", dir_ / run, false);
  }
}

TEST_F(SolidSynthesisRuns, SameBytesWithTheScanKernelsOfEveryInstructionSet) {
  // The float scan only filters: its candidates are decided in double, so the narrower kernels
  // (those of CPUs without AVX-512 or AVX2, other float roundings) give the same sets and bytes.
  for (const ScanIsa isa : supported_scan_isas()) {
    if (isa == best_scan_isa())
      continue;
    const std::string name = scan_isa_name(isa);
    const fs::path out = dir_ / ("isa_" + name);
    const auto outcome = test::run_command(
        test::texsim_under_mpirun(2, "-x TEXSIM_SCAN_ISA=" + name) + " " +
        (test::source_dir() / "config/solid_synthesis/smoke.yaml").string() +
        " --set output.dir=" + out.string() +
        " --set solid_synthesis.similarity.cache_dir=" + (dir_ / ("cache_isa_" + name)).string());
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
    expect_same_volumes(dir_ / "n2", out, true);
  }
}

TEST_F(SolidSynthesisRuns, RestartFromMidPyramidCheckpointGivesTheSameBytes) {
  for (const int ranks : {2, 3}) {
    const fs::path copy = dir_ / with_ranks("killed_n", ranks);
    fs::copy(dir_ / "n2", copy, fs::copy_options::recursive);
    for (int level = kLastKeptLevel + 1; level <= kFinestLevel; ++level)
      ASSERT_TRUE(fs::remove(test::checkpoint_file(copy, level)));
    for (const char* file :
         {"summary.json", "solid_synthesis.vdb", "solid_synthesis.pvti",
          "exemplar_coordinates.pvti", "solid_synthesis", "exemplar_coordinates"})
      ASSERT_GT(fs::remove_all(copy / file), 0u) << file;
    const auto outcome = run_smoke(ranks, copy, dir_ / "cache", "--restart");
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
    EXPECT_NE(outcome.output.find("restarted from " +
                                  test::checkpoint_file(copy, kLastKeptLevel).string()),
              std::string::npos)
        << outcome.output;
    // Only the levels after the checkpoint were synthesized again.
    EXPECT_EQ(test::read_summary(copy)["metrics"]["levels"].size(), kFinestLevel - kLastKeptLevel);
    expect_same_volumes(dir_ / "n2", copy, ranks == 2);
  }
}

TEST_F(SolidSynthesisRuns, AnisometricRestartKeepsTheSubvoxelPositions) {
  // Under a slant field the checkpointed positions have fractions: a restart at another rank
  // count from mid-pyramid must read them back whole to end with the same volumes.
  const std::string slant = "--set solid_synthesis.field.type=slant";
  const fs::path full = dir_ / "slant_n2";
  const auto first = run_smoke(2, full, dir_ / "cache", slant);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const fs::path copy = dir_ / "slant_killed_n3";
  fs::copy(full, copy, fs::copy_options::recursive);
  for (int level = kLastKeptLevel + 1; level <= kFinestLevel; ++level)
    ASSERT_TRUE(fs::remove(test::checkpoint_file(copy, level)));
  for (const char* file : {"summary.json", "solid_synthesis.vdb", "solid_synthesis.pvti",
                           "exemplar_coordinates.pvti", "solid_synthesis", "exemplar_coordinates"})
    ASSERT_GT(fs::remove_all(copy / file), 0u) << file;
  const auto restarted = run_smoke(3, copy, dir_ / "cache", slant + " --restart");
  ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
  EXPECT_EQ(test::read_summary(copy)["metrics"]["levels"].size(), kFinestLevel - kLastKeptLevel);
  expect_same_volumes(full, copy, false);
}

TEST_F(SolidSynthesisRuns, SecondRunReadsFeaturesAndSimilaritySetsFromTheCache) {
  const fs::path out = dir_ / "cached";
  const auto outcome = run_smoke(2, out, dir_ / "cache");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_EQ(test::read_summary(out)["metrics"]["exemplar"]["features"], "cache");
  for (const auto& [level, source] :
       test::read_summary(out)["metrics"]["similarity_sets"]["levels"].items())
    EXPECT_EQ(source, "cache") << "stack level " << level;
  expect_same_volumes(dir_ / "n2", out, true);
}

TEST_F(SolidSynthesisRuns, RestartWithAnotherExemplarSettingIsRefused) {
  const fs::path copy = dir_ / "refused";
  fs::copy(dir_ / "n2", copy, fs::copy_options::recursive);
  ASSERT_TRUE(fs::remove(copy / "summary.json"));
  const auto outcome =
      run_smoke(2, copy, dir_ / "cache", "--restart --set solid_synthesis.synthesis.jitter=0.5");
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  EXPECT_NE(outcome.output.find("different configuration"), std::string::npos) << outcome.output;
}

} // namespace
} // namespace texsim
