// Through the binary, as a user runs it: config/solid_synthesis/smoke.yaml (16^3 marble exemplar
// to 32^3, a checkpoint after every pyramid level) gives the same volume bytes at -n 1, 2 and 3;
// a copy of the -n 2 run that lost the checkpoints after level 3 (a job killed mid-pyramid) and is
// continued with --restart, at -n 2 and at -n 3, ends with the same bytes too; and the second run
// reads its appearance space and similarity sets from the cache the first one wrote. The texsim
// runs are child jobs (support/run_command.hpp); this program itself runs on one rank.
#include "support/run_command.hpp"
#include "support/test_data.hpp"

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

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

fs::path checkpoint_path(const fs::path& out, int level) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%09d.h5", level);
  return out / "checkpoints" / name;
}

/// "<prefix><ranks>": a run directory name per rank count.
std::string with_ranks(std::string prefix, int ranks) {
  return prefix.append(std::to_string(ranks));
}

nlohmann::json read_summary(const fs::path& out) {
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in);
}

void expect_same_volumes(const fs::path& a, const fs::path& b) {
  for (const char* file : {"exemplar_coordinates.vti", "solid_synthesis.vti"}) {
    const std::string bytes = read_bytes(a / file);
    EXPECT_FALSE(bytes.empty()) << (a / file);
    EXPECT_TRUE(bytes == read_bytes(b / file)) << file << " differs between " << a << " and " << b;
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
  // .vdb, .vti, slice PNGs, checkpoints, caches, summary.json: all renamed into place.
  EXPECT_TRUE(fs::exists(dir_ / "n2" / "solid_synthesis.vdb"));
  EXPECT_TRUE(test::temporary_files_under(dir_ / "n2").empty());
  EXPECT_TRUE(test::temporary_files_under(dir_ / "cache").empty());
}

TEST_F(SolidSynthesisRuns, SameBytesAtOneTwoAndThreeRanks) {
  for (const int ranks : {1, 3}) {
    const fs::path out = dir_ / with_ranks("n", ranks);
    const auto outcome = run_smoke(ranks, out, dir_ / with_ranks("cache_n", ranks));
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
    expect_same_volumes(dir_ / "n2", out);
  }
}

TEST_F(SolidSynthesisRuns, RestartFromMidPyramidCheckpointGivesTheSameBytes) {
  for (const int ranks : {2, 3}) {
    const fs::path copy = dir_ / with_ranks("killed_n", ranks);
    fs::copy(dir_ / "n2", copy, fs::copy_options::recursive);
    for (int level = kLastKeptLevel + 1; level <= kFinestLevel; ++level)
      ASSERT_TRUE(fs::remove(checkpoint_path(copy, level)));
    for (const char* file : {"summary.json", "solid_synthesis.vti", "exemplar_coordinates.vti"})
      ASSERT_TRUE(fs::remove(copy / file));
    const auto outcome = run_smoke(ranks, copy, dir_ / "cache", "--restart");
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
    EXPECT_NE(
        outcome.output.find("restarted from " + checkpoint_path(copy, kLastKeptLevel).string()),
        std::string::npos)
        << outcome.output;
    // Only the levels after the checkpoint were synthesized again.
    EXPECT_EQ(read_summary(copy)["metrics"]["levels"].size(), kFinestLevel - kLastKeptLevel);
    expect_same_volumes(dir_ / "n2", copy);
  }
}

TEST_F(SolidSynthesisRuns, SecondRunReadsFeaturesAndSimilaritySetsFromTheCache) {
  const fs::path out = dir_ / "cached";
  const auto outcome = run_smoke(2, out, dir_ / "cache");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_EQ(read_summary(out)["metrics"]["exemplar"]["features"], "cache");
  for (const auto& [level, source] :
       read_summary(out)["metrics"]["similarity_sets"]["levels"].items())
    EXPECT_EQ(source, "cache") << "stack level " << level;
  expect_same_volumes(dir_ / "n2", out);
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
