#pragma once
// A turk_rd run through the binary, as a user starts it: a config written to a scratch folder,
// texsim under mpirun -n 2, and the summary's per-stage metrics read back.
#include "support/run_command.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <string>

namespace texsim::test {

/// metrics.stages of the run `name` (in scratch folder `scratch`) whose `turk_rd:` section is
/// `section` (YAML lines indented by two); a nonzero exit code fails the test.
inline nlohmann::json turk_stages(const std::string& scratch, const std::string& name, int seed,
                                  const std::string& section) {
  const auto dir = scratch_dir(scratch);
  const auto config = dir / (name + ".yaml");
  std::ofstream(config) << "pipeline: turk_rd\nseed: " << seed
                        << "\noutput: {dir: " << (dir / name).string()
                        << ", every: 100000}\nturk_rd:\n"
                        << section;
  const auto outcome = run_command(texsim_under_mpirun(2) + " " + config.string() + " --quiet");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  std::ifstream in(dir / name / "summary.json");
  return nlohmann::json::parse(in)["metrics"]["stages"];
}

} // namespace texsim::test
