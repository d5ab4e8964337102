// Runs the texsim binary as a user would and checks exit codes, messages and outputs.
#include "app/command_line.hpp"
#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "support/run_command.hpp"
#include "support/vtk_array_type.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {
namespace fs = std::filesystem;

using texsim::test::run_command;
using texsim::test::texsim_command;
using texsim::test::texsim_under_mpirun;

fs::path source(const std::string& relative) {
  return fs::path(TEXSIM_SOURCE_DIR) / relative;
}

fs::path scratch(const std::string& name) {
  const auto dir = fs::temp_directory_path() / ("texsim_cli_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

fs::path write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

TEST(Cli, HelpAndVersion) {
  const auto help = run_command(texsim_command() + " --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("usage:"), std::string::npos);
  const auto version = run_command(texsim_command() + " --version");
  EXPECT_EQ(version.exit_code, 0);
  for (const char* part : {"texsim ", "git ", "PETSc 3.", "HDF5 1.", "VTK 9.", "OpenVDB 10"})
    EXPECT_NE(version.output.find(part), std::string::npos) << part << " in " << version.output;
}

TEST(Cli, ParsesOwnOptionsAndPassesPetscOptionsOn) {
  const char* argv[] = {"texsim",    "run.yaml", "--set", "a.b=1",   "-ksp_type", "cg",
                        "--restart", "-pc_type", "gamg",  "--quiet", "-ksp_view"};
  const auto line = texsim::app::parse_command_line(11, argv);
  EXPECT_EQ(line.config_paths, std::vector<std::string>{"run.yaml"});
  EXPECT_EQ(line.overrides, std::vector<std::string>{"a.b=1"});
  EXPECT_EQ(line.restart, "latest");
  EXPECT_TRUE(line.quiet);
  EXPECT_EQ(line.petsc_args, (std::vector<std::string>{"texsim", "-ksp_type", "cg", "-pc_type",
                                                       "gamg", "-ksp_view"}));
  const char* with_path[] = {"texsim", "--restart", "out/checkpoints/step_000000010.h5", "r.yaml"};
  EXPECT_EQ(texsim::app::parse_command_line(4, with_path).restart,
            "out/checkpoints/step_000000010.h5");
}

TEST(Cli, UnknownOptionIsAnInputErrorWithHint) {
  const auto outcome = run_command(texsim_command() + " config.yaml --quite");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.output.find("unknown option --quite (did you mean --quiet?)"),
            std::string::npos)
      << outcome.output;
}

TEST(Cli, MissingConfigFileExitsTwoNamingTheFile) {
  const auto outcome = run_command(texsim_under_mpirun(2) + " /nonexistent/run.yaml");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.output.find("/nonexistent/run.yaml: no such file"), std::string::npos)
      << outcome.output;
}

TEST(Cli, BadValueExitsTwoOnAllRanksWithOneMessage) {
  const auto dir = scratch("bad_value");
  const auto config = write_file(dir / "bad.yaml", "pipeline: mesh_prep\noutput: {every: -3}\n");
  const auto outcome = run_command(texsim_under_mpirun(3) + " " + config.string());
  EXPECT_EQ(outcome.exit_code, 2);
  const std::string expected = "output.every: expected a positive integer, got -3";
  const auto first = outcome.output.find(expected);
  ASSERT_NE(first, std::string::npos) << outcome.output;
  EXPECT_EQ(outcome.output.find(expected, first + 1), std::string::npos) << "printed twice";
  EXPECT_FALSE(fs::exists(dir / "out")) << "nothing may be written on bad input";
}

TEST(Cli, UnknownKeyGetsDidYouMean) {
  const auto dir = scratch("unknown_key");
  const auto config = write_file(dir / "typo.yaml", "pipeline: mesh_prep\nseeed: 4\n"
                                                    "mesh_prep: {input: {generator: torus}}\n");
  const auto outcome = run_command(texsim_command() + " validate " + config.string());
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.output.find("unknown key 'seeed' (did you mean 'seed'?)"), std::string::npos)
      << outcome.output;
}

TEST(Cli, ValidateTakesSeveralConfigsAndNamesTheInvalidOne) {
  const auto dir = scratch("several");
  const auto typo = write_file(dir / "typo.yaml", "pipeline: mesh_prep\nseeed: 4\n"
                                                  "mesh_prep: {input: {generator: torus}}\n");
  const auto valid = source("config/mesh_prep/smoke.yaml").string();
  const auto outcome = run_command(texsim_under_mpirun(2) + " validate " + valid + " " +
                                   typo.string() + " " + valid);
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.output.find(valid + ": valid mesh_prep config"), std::string::npos)
      << outcome.output;
  EXPECT_NE(outcome.output.find("typo.yaml: unknown key 'seeed'"), std::string::npos)
      << outcome.output;
  EXPECT_EQ(outcome.output.find("MPI_ABORT"), std::string::npos) << outcome.output;
  const auto first = outcome.output.find(valid + ": valid");
  EXPECT_EQ(outcome.output.find(valid + ": valid", first + 1), std::string::npos)
      << "validation went on past the invalid config";
}

TEST(Cli, UnknownPipelineListsTheRegisteredOnes) {
  const auto dir = scratch("unknown_pipeline");
  const auto config = write_file(dir / "p.yaml", "pipeline: warp_drive\n");
  const auto outcome = run_command(texsim_command() + " validate " + config.string());
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.output.find("pipeline: expected one of fem_rd, fluid_lapped, mesh_prep"),
            std::string::npos)
      << outcome.output;
}

TEST(Cli, SetOverrideIsValidatedLikeTheFile) {
  const auto outcome = run_command(texsim_command() + " validate " +
                                   source("config/default.yaml").string() + " --set seed=-1");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.output.find("seed: expected a non-negative integer, got -1"), std::string::npos)
      << outcome.output;
}

/// The shipped configs (config/**/*.yaml) that name files under ${TEXSIM_DATA} (data/, put there
/// by scripts/fetch-data), or the others.
std::vector<fs::path> shipped_configs(bool naming_data) {
  std::vector<fs::path> configs;
  for (const auto& entry : fs::recursive_directory_iterator(source("config"))) {
    if (entry.path().extension() != ".yaml")
      continue;
    std::stringstream text;
    text << std::ifstream(entry.path()).rdbuf();
    if ((text.str().find("${TEXSIM_DATA}") != std::string::npos) == naming_data)
      configs.push_back(entry.path());
  }
  return configs;
}

/// All of them in one `texsim validate`, which names the first invalid one.
void expect_valid(const std::vector<fs::path>& configs) {
  ASSERT_FALSE(configs.empty());
  std::string command = texsim_command() + " validate --quiet";
  for (const auto& config : configs)
    command.append(" ").append(config.string());
  const auto outcome = run_command(command, source(""));
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
}

TEST(Cli, EveryShippedConfigWithoutDataValidates) {
  expect_valid(shipped_configs(false));
}

TEST(CliOnRealData, EveryShippedConfigNamingDataValidates) {
  if (!fs::exists(source("data")))
    GTEST_SKIP() << "data/ is absent: run scripts/fetch-data to validate the configs that use it";
  expect_valid(shipped_configs(true));
}

TEST(Cli, RunRefusesToOverwriteAnotherRun) {
  const auto dir = scratch("overwrite");
  const auto out = dir / "out";
  const std::string common = texsim_command() + " --quiet " +
                             source("config/mesh_prep/smoke.yaml").string() +
                             " --set output.dir=" + out.string();
  ASSERT_EQ(run_command(common).exit_code, 0);
  const auto before = fs::last_write_time(out / "summary.json");
  const auto second = run_command(common);
  EXPECT_EQ(second.exit_code, 2);
  EXPECT_NE(second.output.find("already holds a run"), std::string::npos) << second.output;
  EXPECT_EQ(fs::last_write_time(out / "summary.json"), before);
}

TEST(Cli, SmokeRunAtTwoRanksWritesSummaryAndParaViewFiles) {
  const auto dir = scratch("smoke");
  const auto out = dir / "out";
  const auto outcome =
      run_command(texsim_under_mpirun(2) + " " + source("config/mesh_prep/smoke.yaml").string() +
                  " --set output.dir=" + out.string());
  ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  std::ifstream in(out / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["pipeline"], "mesh_prep");
  EXPECT_EQ(summary["ranks"], 2);
  EXPECT_EQ(summary["threads"], 1);
  EXPECT_GT(summary["wall_s"].get<double>(), 0.0);
  EXPECT_FALSE(summary["stages"].empty());
  EXPECT_EQ(summary["config_hash"].get<std::string>().size(), 16u);
  EXPECT_TRUE(summary["metrics"].is_object());
  bool has_pvd = false;
  for (const auto& output : summary["outputs"]) {
    EXPECT_TRUE(fs::exists(output.get<std::string>())) << output;
    has_pvd |= fs::path(output.get<std::string>()).extension() == ".pvd";
  }
  EXPECT_TRUE(has_pvd);
  // Every file was written under a temporary name and renamed: none is left behind.
  for (const auto& entry : fs::recursive_directory_iterator(out))
    EXPECT_FALSE(texsim::final_name_of_temporary(entry.path().filename().string()))
        << "left behind: " << entry.path();
  // Ids and ranks read back as integers, not as Float64.
  using texsim::test::ArrayAssociation;
  using texsim::test::vtk_array_type;
  EXPECT_EQ(vtk_array_type(out / "surface.pvtp", ArrayAssociation::point, "global_id"),
            VTK_TYPE_INT32);
  EXPECT_EQ(vtk_array_type(out / "surface.pvtp", ArrayAssociation::cell, "rank"), VTK_TYPE_INT32);
  EXPECT_EQ(vtk_array_type(out / "surface.pvtp", ArrayAssociation::point, "vertex_area"),
            VTK_DOUBLE);
}

} // namespace
