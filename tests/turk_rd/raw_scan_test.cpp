// turk_rd on a raw marching-cubes surface through the binary (config/turk_rd/raw_scan.yaml, data
// from scripts/fetch-data): the MRI head runs after mesh.repair: fix; dt = 1 is far above the
// explicit stability limit of its cells, so each step runs as ceil(dt / (safety limit))
// substeps instead of being refused; the cell-area spread is reported.
#include "support/run_command.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace texsim {
namespace {
namespace fs = std::filesystem;

nlohmann::json run_head(const fs::path& out, const std::string& options) {
  const auto outcome =
      test::run_command(test::texsim_under_mpirun(2) + " " +
                            (test::source_dir() / "config/turk_rd/raw_scan.yaml").string() +
                            " --set output.dir=" + out.string() +
                            " --set turk_rd.stages.spots.steps=2 --set turk_rd.cells.count=4000 "
                            "--set turk_rd.cells.relaxation.iterations=10 " +
                            options,
                        test::source_dir());
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  EXPECT_NE(outcome.output.find("is above the explicit stability limit"), std::string::npos)
      << outcome.output;
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in)["metrics"];
}

TEST(TurkRdRawScanOnRealData, HeadScanRunsWithStableSubstepsAndReportsTheAreaSpread) {
  const std::string name = "scans/ch2_head_mc_2mm.ply";
  if (test::real_data(name).empty())
    GTEST_SKIP() << test::missing_data_message(name);
  const auto dir = test::scratch_dir("turk_rd_raw_scan");
  const auto m = run_head(dir / "default", "");
  EXPECT_EQ(m["mesh_repair"]["non_manifold_edges"], 42);
  const auto& stage = m["stages"]["spots"];
  const double limit = stage["max_stable_dt"].get<double>();
  ASSERT_LT(limit, 1.0);
  EXPECT_EQ(stage["substeps"].get<std::int64_t>(), std::int64_t(std::ceil(1.0 / (0.9 * limit))));
  for (const auto& [species, values] : stage["species"].items()) {
    EXPECT_TRUE(std::isfinite(values["min"].get<double>())) << species;
    EXPECT_TRUE(std::isfinite(values["max"].get<double>())) << species;
  }
  const auto& cells = m["cells"];
  EXPECT_LT(cells["area_min"].get<double>(), cells["area_median"].get<double>());
  EXPECT_LT(cells["area_median"].get<double>(), cells["area_max"].get<double>());

  const auto safer = run_head(dir / "safer", "--set turk_rd.stability_safety=0.45");
  EXPECT_EQ(safer["stages"]["spots"]["substeps"].get<std::int64_t>(),
            std::int64_t(std::ceil(1.0 / (0.45 * limit))));
}

} // namespace
} // namespace texsim
