// Restart equivalence and rank independence through the binary, as a user runs it:
// config/turk_rd/smoke.yaml (a two-stage cascade of 40 + 40 steps, checkpoints every 20) runs
// uninterrupted on 2 ranks into A. Copies of A lose every checkpoint after step 20 and the summary
// (a job killed in the middle of the first stage) and are continued with --restart on 2 and on 1
// rank, crossing the stage boundary after the restart; a full run on 3 ranks starts afresh. Every
// final checkpoint must equal A's bit for bit. A restart with a changed config is refused with
// exit code 2, naming the checkpoint, and writes nothing.
#include "io/checkpoint_store.hpp"
#include "par/comm.hpp"
#include "support/output_files.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"
#include "support/vtk_array_type.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace texsim {
namespace {
namespace fs = std::filesystem;

constexpr std::int64_t kKilledAfter = 20;
constexpr std::int64_t kFinalStep = 80;

test::CommandOutcome run_smoke(int ranks, const fs::path& out, const std::string& options = "") {
  return test::run_command(test::texsim_under_mpirun(ranks) + " " +
                           (test::source_dir() / "config/turk_rd/smoke.yaml").string() +
                           " --set checkpoint.every=20 --set checkpoint.keep=10 --set output.dir=" +
                           out.string() + " " + options);
}

void copy_killed(const fs::path& run, const fs::path& copy) {
  fs::copy(run, copy, fs::copy_options::recursive);
  for (std::int64_t step = kKilledAfter + 20; step <= kFinalStep; step += 20)
    ASSERT_TRUE(fs::remove(test::checkpoint_file(copy, step)));
  ASSERT_TRUE(fs::remove(copy / "summary.json"));
}

/// Every dataset of the newest checkpoint, as raw values in cell-id order.
struct FinalState {
  std::int64_t step = -1;
  std::int64_t stage = -1;
  std::map<std::string, std::vector<double>> fields;
};

FinalState read_final_state(const fs::path& out) {
  const auto hash = test::read_summary(out)["config_hash"].get<std::string>();
  const io::CheckpointStore store(par::world(), out / "checkpoints", hash, 10);
  const auto reader = store.resolve("latest").reader;
  FinalState state;
  state.step = reader.step();
  state.stage = reader.attribute_int64("stage");
  const auto rows = reader.global_count("cell_id");
  std::vector<std::int64_t> ids(rows);
  reader.read<std::int64_t>("cell_id", ids, 0, rows);
  for (const auto& name : reader.dataset_names()) {
    if (name == "cell_id")
      continue;
    std::vector<double> values(rows), by_id(rows);
    reader.read<double>(name, values, 0, rows);
    for (std::size_t row = 0; row < rows; ++row)
      by_id.at(std::size_t(ids[row])) = values[row];
    state.fields[name] = by_id;
  }
  return state;
}

void expect_same_bits(const FinalState& a, const FinalState& b) {
  EXPECT_EQ(a.step, kFinalStep);
  EXPECT_EQ(b.step, kFinalStep);
  EXPECT_EQ(a.stage, b.stage);
  // The running stage's a and b and the first stage's spots_a and spots_b.
  ASSERT_EQ(a.fields.size(), 4u);
  for (const auto& [name, values] : a.fields) {
    ASSERT_TRUE(b.fields.contains(name)) << name;
    const auto& other = b.fields.at(name);
    ASSERT_EQ(values.size(), other.size());
    EXPECT_EQ(std::memcmp(values.data(), other.data(), values.size() * sizeof(double)), 0)
        << name << " differs";
  }
}

class TurkRdRestart : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = test::scratch_dir("turk_rd_restart");
    uninterrupted_ = run_smoke(2, dir_ / "a", "--quiet");
  }
  void SetUp() override {
    ASSERT_EQ(uninterrupted_.exit_code, 0) << uninterrupted_.output;
    ASSERT_TRUE(fs::exists(test::checkpoint_file(run_a(), kKilledAfter)));
    ASSERT_TRUE(fs::exists(test::checkpoint_file(run_a(), kFinalStep)));
  }
  static fs::path run_a() { return dir_ / "a"; }
  static fs::path dir() { return dir_; }

private:
  static inline fs::path dir_;
  static inline test::CommandOutcome uninterrupted_;
};

TEST_F(TurkRdRestart, RestartAcrossTheStageBoundaryEndsBitIdentical) {
  for (const int ranks : {2, 1}) {
    const fs::path b = dir() / ("restart_n" + std::to_string(ranks));
    ASSERT_NO_FATAL_FAILURE(copy_killed(run_a(), b));
    const auto restarted = run_smoke(ranks, b, "--restart");
    ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
    EXPECT_NE(
        restarted.output.find("restarted from " + test::checkpoint_file(b, kKilledAfter).string()),
        std::string::npos)
        << restarted.output;
    EXPECT_EQ(test::stage_calls(test::read_summary(b), "rd_step"), kFinalStep - kKilledAfter);
    expect_same_bits(read_final_state(run_a()), read_final_state(b));
    // The frame series continue where they stopped: the same entries as the uninterrupted run.
    for (const char* series : {"turk_rd_surface.pvd", "turk_rd_cells.pvd", "turk_rd_bump.pvd"})
      EXPECT_EQ(test::read_text(b / series), test::read_text(run_a() / series)) << series;
    EXPECT_TRUE(test::temporary_files_under(b).empty());
  }
}

TEST_F(TurkRdRestart, CellFramesHoldIntegerIdsAndNoTemporaryFileIsLeft) {
  EXPECT_TRUE(test::temporary_files_under(run_a()).empty());
  std::vector<fs::path> frames;
  for (const auto& entry : fs::directory_iterator(run_a() / "frames"))
    if (entry.path().filename().string().starts_with("cells_") &&
        entry.path().extension() == ".pvtp")
      frames.push_back(entry.path());
  ASSERT_FALSE(frames.empty());
  std::sort(frames.begin(), frames.end());
  using test::ArrayAssociation;
  EXPECT_EQ(test::vtk_array_type(frames.back(), ArrayAssociation::cell, "cell_id"), VTK_TYPE_INT64);
  EXPECT_EQ(test::vtk_array_type(frames.back(), ArrayAssociation::cell, "pattern"), VTK_DOUBLE);
}

TEST_F(TurkRdRestart, ThreeRanksGiveTheSameBitsAsTwo) {
  const fs::path c = dir() / "n3";
  const auto run = run_smoke(3, c, "--quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  expect_same_bits(read_final_state(run_a()), read_final_state(c));
}

TEST_F(TurkRdRestart, WithAnotherConfigIsRefusedNamingTheCheckpoint) {
  const fs::path d = dir() / "changed";
  ASSERT_NO_FATAL_FAILURE(copy_killed(run_a(), d));
  const auto killed_at = test::checkpoint_file(d, kKilledAfter);
  const auto written = fs::last_write_time(killed_at);
  const auto refused = run_smoke(2, d, "--restart --set turk_rd.stages.spots.model.s=0.06");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find(killed_at.string() + ": written by a different configuration"),
            std::string::npos)
      << refused.output;
  EXPECT_EQ(fs::last_write_time(killed_at), written);
  EXPECT_FALSE(fs::exists(d / "summary.json"));
  EXPECT_FALSE(fs::exists(test::checkpoint_file(d, kFinalStep)));
}

} // namespace
} // namespace texsim
