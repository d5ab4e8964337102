// fem_rd on raw marching-cubes surfaces through the binary, as a user runs it
// (config/fem_rd/raw_scan.yaml, data from scripts/fetch-data): the MRI head with non-manifold
// edges runs after mesh.repair: fix (and is refused by strict), the probe picks BoomerAMG there
// and Jacobi on a clean sphere, iterations per step stay bounded, two runs give the same bytes;
// on the slivered CT skull, Jacobi warns naming mesh.remesh and remeshing restores it.
#include "support/run_command.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace texsim {
namespace {
namespace fs = std::filesystem;

const char* const kHead = "scans/ch2_head_mc_2mm.ply";
const char* const kSkull = "scans/skull_ct_mc.ply";

test::CommandOutcome run_config(const std::string& config, const fs::path& out,
                                const std::string& options) {
  return test::run_command(test::texsim_under_mpirun(2) + " " +
                               (test::source_dir() / config).string() +
                               " --set output.dir=" + out.string() + " " + options,
                           test::source_dir());
}

nlohmann::json metrics(const fs::path& out) {
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in)["metrics"];
}

std::string bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

#define REQUIRE_DATA(name)                                                                         \
  if (test::real_data(name).empty())                                                               \
  GTEST_SKIP() << test::missing_data_message(name)

TEST(FemRdRawScanOnRealData, HeadScanRunsAfterFixWithAmgAndTheSameBytesTwice) {
  REQUIRE_DATA(kHead);
  const auto dir = test::scratch_dir("fem_rd_raw_scan_head");
  const std::string options = "--set fem_rd.time.steps=2 --set output.every=2 "
                              "--set fem_rd.partition=morton --quiet";
  for (const auto* name : {"a", "b"}) {
    const auto outcome = run_config("config/fem_rd/raw_scan.yaml", dir / name, options);
    ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  }
  const auto m = metrics(dir / "a");
  EXPECT_EQ(m["mesh_repair"]["mode"], "fix");
  EXPECT_EQ(m["mesh_repair"]["non_manifold_edges"], 42);
  EXPECT_GT(m["mesh_repair"]["split_added_vertices"].get<int>(), 0);
  EXPECT_GT(m["mesh_repair"]["dropped_components"].get<int>(), 100);
  const auto& solver = m["linear_solver"];
  EXPECT_EQ(solver["preconditioner"], "boomeramg");
  EXPECT_EQ(solver["jacobi_probe"]["converged"], false);
  ASSERT_EQ(solver["iterations_per_step"].size(), 2u);
  // Measured 7 and 12 (CG + Jacobi: 240 and 522).
  EXPECT_LE(solver["iterations_per_step_max"].get<int>(), 40);
  for (const auto* piece :
       {"frames/step_000000002/step_000000002_0.vtu", "frames/step_000000002/step_000000002_1.vtu"})
    EXPECT_TRUE(bytes(dir / "a" / piece) == bytes(dir / "b" / piece)) << piece;
}

TEST(FemRdRawScanOnRealData, StrictRefusesTheHeadScanNamingWhatNeedsRepair) {
  REQUIRE_DATA(kHead);
  const auto out = test::scratch_dir("fem_rd_raw_scan_strict") / "run";
  const auto outcome =
      run_config("config/fem_rd/raw_scan.yaml", out, "--set fem_rd.mesh.repair=strict");
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  EXPECT_NE(outcome.output.find(std::string(kHead) +
                                ": the mesh needs repair (mesh.repair: strict): 12 duplicate "
                                "triangles (first: triangle 1793 (484, 505, 503) repeats "
                                "triangle 525); 42 non-manifold edges (first: vertices 484-505 "
                                "shared by 4 triangles); 32 non-manifold vertices"),
            std::string::npos)
      << outcome.output;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

TEST(FemRdRawScan, CleanSphereKeepsJacobi) {
  const auto out = test::scratch_dir("fem_rd_raw_scan_clean") / "run";
  const auto outcome =
      run_config("config/fem_rd/smoke.yaml", out, "--set fem_rd.time.steps=2 --quiet");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  const auto solver = metrics(out)["linear_solver"];
  EXPECT_EQ(solver["preconditioner"], "jacobi");
  EXPECT_EQ(solver["jacobi_probe"]["converged"], true);
}

TEST(FemRdRawScanOnRealData, SliversWarnNamingRemeshAndRemeshingRestoresJacobi) {
  REQUIRE_DATA(kSkull);
  const auto dir = test::scratch_dir("fem_rd_raw_scan_skull");
  const std::string skull = std::string("--set fem_rd.mesh.file=data/") + kSkull +
                            " --set fem_rd.mesh.scale=0.12 --set fem_rd.time.steps=2";
  const auto jacobi = run_config("config/fem_rd/raw_scan.yaml", dir / "jacobi",
                                 skull + " --set fem_rd.solver.preconditioner=jacobi");
  ASSERT_EQ(jacobi.exit_code, 0) << jacobi.output;
  EXPECT_NE(jacobi.output.find("warning: fem_rd: CG needed"), std::string::npos) << jacobi.output;
  EXPECT_NE(jacobi.output.find("fem_rd.mesh.remesh: {edge_length: L}"), std::string::npos);
  EXPECT_GT(metrics(dir / "jacobi")["linear_solver"]["iterations_per_step_max"].get<int>(), 400);

  // Remeshed at about the mean edge length (0.45): measured 27 iterations per step with Jacobi.
  const auto remeshed = run_config("config/fem_rd/raw_scan.yaml", dir / "remeshed",
                                   skull + " --set fem_rd.mesh.remesh.edge_length=0.45 --quiet");
  ASSERT_EQ(remeshed.exit_code, 0) << remeshed.output;
  const auto m = metrics(dir / "remeshed");
  EXPECT_EQ(m["linear_solver"]["preconditioner"], "jacobi");
  EXPECT_LE(m["linear_solver"]["iterations_per_step_max"].get<int>(), 60);
  EXPECT_EQ(m["mesh_remesh"]["edge_length"], 0.45);
}

} // namespace
} // namespace texsim
