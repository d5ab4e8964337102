// Fig. 5's pattern classes through the binary, measured by summary.json's locked_phase on a
// smaller sphere than the figure's (level 5, radius 40, t = 500, 2 ranks): inside the 1:4 locking
// tongue (Gamma 0.3) the response stands still against the forcing, with several
// phases when v does not diffuse (delta = 0: the multi-phase patterns of Lin et al.) and one
// phase when it diffuses five times faster than u (delta = 5: the pattern is in the amplitude);
// outside it (Gamma 0.2, the figure's config) the phase drifts.
#include "support/output_files.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace texsim {
namespace {
namespace fs = std::filesystem;

nlohmann::json locked_phase(const std::string& name, const std::string& settings) {
  const fs::path out = test::scratch_dir("forced_oscillator_phases") / name;
  fs::remove_all(out);
  const auto outcome = test::run_command(
      test::texsim_under_mpirun(2) + " " +
      (test::source_dir() / "config/fem_rd/forced_oscillator.yaml").string() +
      " --quiet --set fem_rd.mesh.level=5 --set fem_rd.mesh.radius=40 --set output.every=100000"
      " --set output.dir=" +
      out.string() + " " + settings);
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  return test::read_summary(out)["metrics"]["locked_phase"];
}

TEST(ForcedOscillatorPhases, WithoutVDiffusionTheLockedSurfaceTakesSeveralPhases) {
  const auto phases =
      locked_phase("delta0", "--set fem_rd.model.gamma=0.3 --set fem_rd.model.delta=0");
  EXPECT_TRUE(phases["locked"].get<bool>()) << phases.dump();
  EXPECT_GE(phases["phases"].get<int>(), 3) << phases.dump();
  EXPECT_LT(phases["order_1"].get<double>(), 0.7) << phases.dump();
}

TEST(ForcedOscillatorPhases, WithFastVDiffusionTheLockedSurfaceTakesOnePhase) {
  const auto phases =
      locked_phase("delta5", "--set fem_rd.model.gamma=0.3 --set fem_rd.model.delta=5");
  EXPECT_TRUE(phases["locked"].get<bool>()) << phases.dump();
  EXPECT_EQ(phases["phases"].get<int>(), 1) << phases.dump();
  EXPECT_GT(phases["order_1"].get<double>(), 0.9) << phases.dump();
}

TEST(ForcedOscillatorPhases, OutsideTheLockingTongueThePhaseDrifts) {
  const auto phases = locked_phase("gamma02", "");
  EXPECT_FALSE(phases["locked"].get<bool>()) << phases.dump();
  EXPECT_GT(std::abs(phases["phase_drift_deg"].get<double>()), 20.0) << phases.dump();
  EXPECT_EQ(phases["phases"].get<int>(), 0);
}

} // namespace
} // namespace texsim
