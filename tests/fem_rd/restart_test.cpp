// Restart equivalence through the binary, as a user does it: config/fem_rd/smoke.yaml (set to 40
// steps with checkpoints at 20 and 40) runs uninterrupted into A; a copy of A loses its last
// checkpoint and its summary.json (a job killed after the middle checkpoint) and is continued with
// --restart. The final checkpoints must agree bit for bit at the same rank count and to solver
// tolerance at another; a restart with a changed config must be refused. The texsim runs are child
// jobs started with a clean environment (support/run_command.hpp); this program itself runs on one
// rank.
#include "io/checkpoint_store.hpp"
#include "par/comm.hpp"
#include "support/output_files.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"
#include "support/vtk_array_type.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace texsim {
namespace {
namespace fs = std::filesystem;

constexpr std::int64_t kMiddleStep = 20; // checkpoint.every
constexpr std::int64_t kFinalStep = 40;

/// smoke.yaml with the smoothing running through step 29 and the RD matrices rebuilt every 7
/// steps, so that the middle checkpoint falls inside the smoothing and between two rebuilds: the
/// restart must restore both the surface and the one the matrices were built on. The default
/// (Scotch) partition is a pure function of the mesh and the rank count, so the runs agree bit
/// for bit.
test::CommandOutcome run_smoke(int ranks, const fs::path& out, const std::string& options = "") {
  return test::run_command(test::texsim_under_mpirun(ranks) + " " +
                           (test::source_dir() / "config/fem_rd/smoke.yaml").string() +
                           " --set fem_rd.time.steps=40 --set checkpoint.every=20"
                           " --set fem_rd.smoothing.steps=30"
                           " --set fem_rd.smoothing.rebuild_every=7 --set output.dir=" +
                           out.string() + " " + options);
}

/// A's state as a killed job leaves it after the middle checkpoint, in `copy`.
void copy_killed_after_middle_checkpoint(const fs::path& run, const fs::path& copy) {
  fs::copy(run, copy, fs::copy_options::recursive);
  ASSERT_TRUE(fs::remove(test::checkpoint_file(copy, kFinalStep)));
  ASSERT_TRUE(fs::remove(copy / "summary.json"));
}

/// The datasets of the newest checkpoint in `out`, opened and verified the way texsim does it.
struct FinalState {
  std::int64_t step = -1;
  std::vector<std::int64_t> input_vertex_id;       ///< input id of each row
  std::map<std::string, std::vector<double>> real; ///< species_*, positions, matrix_positions
  std::map<std::string, int> components;
};

FinalState read_final_state(const fs::path& out) {
  const auto hash = test::read_summary(out)["config_hash"].get<std::string>();
  const io::CheckpointStore store(par::world(), out / "checkpoints", hash, 3);
  const auto reader = store.resolve("latest").reader;
  FinalState state;
  state.step = reader.step();
  for (const auto& name : reader.dataset_names()) {
    const auto rows = reader.global_count(name);
    const int components = reader.components(name);
    if (reader.type(name) == io::ScalarType::int64) {
      EXPECT_EQ(name, "input_vertex_id");
      state.input_vertex_id.resize(rows);
      reader.read<std::int64_t>(name, state.input_vertex_id, 0, rows);
      continue;
    }
    auto& values = state.real[name];
    values.resize(rows * components);
    reader.read<double>(name, values, 0, rows);
    state.components[name] = components;
  }
  return state;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

/// Largest difference between `a` and `b` compared by input vertex id, relative to max |a|.
double relative_difference(const FinalState& a, const FinalState& b, const std::string& name) {
  const int c = a.components.at(name);
  std::vector<std::size_t> row_in_b(b.input_vertex_id.size());
  for (std::size_t row = 0; row < b.input_vertex_id.size(); ++row)
    row_in_b.at(std::size_t(b.input_vertex_id[row])) = row;
  const auto& va = a.real.at(name);
  const auto& vb = b.real.at(name);
  double scale = 0, difference = 0;
  for (std::size_t row = 0; row < a.input_vertex_id.size(); ++row)
    for (int k = 0; k < c; ++k) {
      const double x = va[c * row + k];
      const double y = vb[c * row_in_b[std::size_t(a.input_vertex_id[row])] + k];
      scale = std::max(scale, std::abs(x));
      difference = std::max(difference, std::abs(x - y));
    }
  return difference / scale;
}

void expect_restarted_at_middle(const test::CommandOutcome& outcome, const fs::path& out) {
  const std::string line = "restarted from " + test::checkpoint_file(out, kMiddleStep).string() +
                           " at step " + std::to_string(kMiddleStep);
  EXPECT_NE(outcome.output.find(line), std::string::npos) << outcome.output;
  EXPECT_EQ(test::stage_calls(test::read_summary(out), "rd_step"), kFinalStep - kMiddleStep);
}

/// Runs A once for all tests; each test continues its own copy.
class FemRdRestart : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = test::scratch_dir("fem_rd_restart");
    uninterrupted_ = run_smoke(2, run_a(), "--quiet");
  }
  void SetUp() override {
    ASSERT_EQ(uninterrupted_.exit_code, 0) << uninterrupted_.output;
    ASSERT_TRUE(fs::exists(test::checkpoint_file(run_a(), kMiddleStep)));
    ASSERT_TRUE(fs::exists(test::checkpoint_file(run_a(), kFinalStep)));
  }
  static fs::path run_a() { return dir_ / "a"; }
  static fs::path dir() { return dir_; }

private:
  static inline fs::path dir_;
  static inline test::CommandOutcome uninterrupted_;
};

TEST_F(FemRdRestart, AtTheSameRankCountEndsBitIdentical) {
  const fs::path b = dir() / "b";
  ASSERT_NO_FATAL_FAILURE(copy_killed_after_middle_checkpoint(run_a(), b));
  const auto restarted = run_smoke(2, b, "--restart");
  ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
  expect_restarted_at_middle(restarted, b);

  const FinalState a = read_final_state(run_a());
  const FinalState r = read_final_state(b);
  EXPECT_EQ(a.step, kFinalStep);
  EXPECT_EQ(r.step, kFinalStep);
  EXPECT_EQ(r.input_vertex_id, a.input_vertex_id);
  ASSERT_EQ(a.real.size(), 4u) << "species_a, species_b, positions, matrix_positions";
  for (const auto& [name, values] : a.real) {
    ASSERT_TRUE(r.real.contains(name)) << name;
    EXPECT_TRUE(same_bits(values, r.real.at(name)))
        << name << " differs after the restart, by " << relative_difference(a, r, name)
        << " relative to its largest value";
  }
  // The frame series continues where it stopped: the same entries as the uninterrupted run.
  EXPECT_EQ(test::read_text(b / "fem_rd.pvd"), test::read_text(run_a() / "fem_rd.pvd"));
  EXPECT_TRUE(test::temporary_files_under(b).empty());
}

TEST(FemRdRestartLoopBasis, AtTheSameRankCountEndsBitIdentical) {
  // The same kill and restart in the C1 Loop basis, whose coefficients live on the whole 3-ring
  // halo and whose frames hold limit points and values.
  const fs::path dir = test::scratch_dir("fem_rd_restart_loop");
  const fs::path a = dir / "a", b = dir / "b";
  const std::string loop = "--set fem_rd.basis=loop";
  const auto uninterrupted = run_smoke(2, a, loop + " --quiet");
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.output;
  ASSERT_NO_FATAL_FAILURE(copy_killed_after_middle_checkpoint(a, b));
  const auto restarted = run_smoke(2, b, loop + " --restart");
  ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
  expect_restarted_at_middle(restarted, b);
  const FinalState x = read_final_state(a), y = read_final_state(b);
  ASSERT_EQ(x.real.size(), 4u);
  for (const auto& [name, values] : x.real)
    EXPECT_TRUE(same_bits(values, y.real.at(name))) << name << " differs after the restart";
  for (int piece = 0; piece < 2; ++piece) {
    const std::string frame =
        "frames/step_000000040/step_000000040_" + std::to_string(piece) + ".vtu";
    EXPECT_EQ(test::read_text(a / frame), test::read_text(b / frame)) << frame;
  }
}

TEST(FemRdRestartForcedOscillator, LockedPhaseSumsSurviveTheRestart) {
  // Fig. 5's model on a small sphere: its 80 steps all fall in the locked-phase window (two
  // response periods, 119 steps of 0.25), so the middle checkpoint holds half-summed Fourier
  // sums that the restart must carry on; summary.json's figures then agree bit for bit.
  const fs::path dir = test::scratch_dir("fem_rd_restart_forced");
  const fs::path a = dir / "a", b = dir / "b";
  const auto run = [&](const fs::path& out, const std::string& options) {
    return test::run_command(
        test::texsim_under_mpirun(2) + " " +
        (test::source_dir() / "config/fem_rd/forced_oscillator.yaml").string() +
        " --set fem_rd.mesh.level=3 --set fem_rd.mesh.radius=10 --set fem_rd.time.steps=80"
        " --set checkpoint.every=40 --set output.every=40 --set output.dir=" +
        out.string() + " " + options);
  };
  const auto uninterrupted = run(a, "--quiet");
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.output;
  fs::copy(a, b, fs::copy_options::recursive);
  ASSERT_TRUE(fs::remove(test::checkpoint_file(b, 80)));
  ASSERT_TRUE(fs::remove(b / "summary.json"));
  const auto restarted = run(b, "--restart");
  ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
  EXPECT_NE(restarted.output.find("at step 40"), std::string::npos) << restarted.output;

  const FinalState x = read_final_state(a), y = read_final_state(b);
  for (const char* name : {"locked_phase_u_0", "locked_phase_u_cos_0", "locked_phase_u_sin_0"}) {
    ASSERT_TRUE(x.real.contains(name)) << name;
    EXPECT_TRUE(same_bits(x.real.at(name), y.real.at(name))) << name;
    EXPECT_NE(x.real.at(name), std::vector<double>(x.real.at(name).size(), 0.0)) << name;
  }
  const auto phases_a = test::read_summary(a)["metrics"]["locked_phase"];
  ASSERT_TRUE(phases_a.contains("order_4")) << phases_a.dump();
  EXPECT_EQ(test::read_summary(b)["metrics"]["locked_phase"].dump(), phases_a.dump());
}

TEST_F(FemRdRestart, FramesHoldIntegerIdsAndNoTemporaryFileIsLeft) {
  EXPECT_TRUE(test::temporary_files_under(run_a()).empty());
  std::vector<fs::path> frames;
  for (const auto& entry : fs::directory_iterator(run_a() / "frames"))
    if (entry.path().extension() == ".pvtu")
      frames.push_back(entry.path());
  ASSERT_FALSE(frames.empty());
  std::sort(frames.begin(), frames.end());
  using test::ArrayAssociation;
  EXPECT_EQ(test::vtk_array_type(frames.back(), ArrayAssociation::cell, "rank"), VTK_TYPE_INT32);
  EXPECT_EQ(test::vtk_array_type(frames.back(), ArrayAssociation::point, "input_vertex_id"),
            VTK_TYPE_INT64);
}

TEST_F(FemRdRestart, AtAnotherRankCountAgreesToSolverTolerance) {
  const fs::path c = dir() / "c";
  ASSERT_NO_FATAL_FAILURE(copy_killed_after_middle_checkpoint(run_a(), c));
  const auto restarted = run_smoke(3, c, "--restart");
  ASSERT_EQ(restarted.exit_code, 0) << restarted.output;
  expect_restarted_at_middle(restarted, c);

  const FinalState a = read_final_state(run_a());
  const FinalState r = read_final_state(c);
  EXPECT_EQ(r.step, kFinalStep);
  ASSERT_EQ(a.real.size(), 4u);
  for (const auto& [name, values] : a.real) {
    ASSERT_TRUE(r.real.contains(name)) << name;
    EXPECT_LT(relative_difference(a, r, name), 1e-7) << name;
  }
}

TEST_F(FemRdRestart, WithAnotherConfigIsRefusedNamingTheCheckpoint) {
  const fs::path d = dir() / "d";
  ASSERT_NO_FATAL_FAILURE(copy_killed_after_middle_checkpoint(run_a(), d));
  const auto middle = test::checkpoint_file(d, kMiddleStep);
  const auto written = fs::last_write_time(middle);
  const auto refused = run_smoke(2, d, "--restart --set fem_rd.model.s=0.03");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find(middle.string() + ": written by a different configuration"),
            std::string::npos)
      << refused.output;
  EXPECT_EQ(fs::last_write_time(middle), written);
  EXPECT_FALSE(fs::exists(d / "summary.json"));
  EXPECT_FALSE(fs::exists(test::checkpoint_file(d, kFinalStep)));
}

} // namespace
} // namespace texsim
