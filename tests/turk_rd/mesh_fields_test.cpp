// Turk's diffusion rates varying over the surface through a per-vertex field of the input mesh,
// run through the binary on 2 ranks: a sphere stored as .vtp with the point array
// width = 1 + 0.3 x - 0.2 y + 0.1 z. With `diffusion_scale: width` the run must match the run
// whose diffusion_scale is the same formula of position (the cells lie on the file's triangles,
// where the interpolated field is the formula up to round-off), and differ from constant rates;
// an initiator `region: width > 1.3` freezes the same cells as the formula does.
// A missing array is refused with exit code 2, naming the file and the arrays it has.
#include "geom/generators.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"
#include "support/vtp_file.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace texsim {
namespace {
namespace fs = std::filesystem;

fs::path write_sphere_with_width(const fs::path& path) {
  const auto mesh = geom::icosphere(3);
  std::vector<double> width;
  for (const auto& p : mesh.positions)
    width.push_back(1 + 0.3 * p.x() - 0.2 * p.y() + 0.1 * p.z());
  return test::write_vtp(path, mesh, {{"width", width}});
}

/// Runs a 300-step spot system on the sphere file with the given diffusion settings; `region`
/// selects initiator cells holding b = 8.
test::CommandOutcome run(const fs::path& dir, const std::string& name, const fs::path& mesh,
                         const std::string& diffusion_lines, const std::string& region = "x > 3") {
  const fs::path config = dir / (name + ".yaml");
  std::ofstream(config) << "pipeline: turk_rd\nseed: 5\noutput: {dir: " << (dir / name).string()
                        << ", every: 300}\nturk_rd:\n  mesh: {file: " << mesh.string()
                        << ", scale: 4}\n  cells: {count: 1200, relaxation: {iterations: 10}}\n"
                        << diffusion_lines
                        << "  stages:\n    spots:\n      model: {type: turing_spots, s: 0.05}\n"
                        << "      steps: 300\n      dt: 0.5\n      initiators:\n"
                        << "        band: {region: \"" << region << "\", set: {b: 8}}\n";
  return test::run_command(test::texsim_under_mpirun(2) + " " + config.string() + " --quiet");
}

nlohmann::json stage_metrics(const fs::path& out) {
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in)["metrics"]["stages"]["spots"];
}

TEST(TurkRdMeshFields, DiffusionScaleFromAPointArrayMatchesTheSameFormulaOfPosition) {
  const auto dir = test::scratch_dir("turk_rd_mesh_fields");
  const auto mesh = write_sphere_with_width(dir / "sphere_width.vtp");
  // The mesh is scaled by 4: the field's formula holds in the file's coordinates, x / 4 here.
  const auto field = run(dir, "field", mesh, "  mesh_fields: [width]\n  diffusion_scale: width\n");
  const auto formula =
      run(dir, "formula", mesh,
          std::string("  diffusion_scale: \"") + "1 + 0.3 * x / 4 - 0.2 * y / 4 + 0.1 * z / 4\"\n");
  const auto constant = run(dir, "constant", mesh, "");
  for (const auto* outcome : {&field, &formula, &constant})
    ASSERT_EQ(outcome->exit_code, 0) << outcome->output;

  // The initiator region from the array selects the same cells as the formula.
  const auto frozen = stage_metrics(dir / "field")["frozen_cells_rank0"].get<int>();
  EXPECT_GT(frozen, 10);
  EXPECT_EQ(frozen, stage_metrics(dir / "formula")["frozen_cells_rank0"].get<int>());
  const auto a = stage_metrics(dir / "field")["species"],
             b = stage_metrics(dir / "formula")["species"],
             c = stage_metrics(dir / "constant")["species"];
  double differs_from_constant = 0;
  for (const char* species : {"a", "b"})
    for (const char* key : {"min", "max", "final_integral"}) {
      const double x = a[species][key].get<double>(), y = b[species][key].get<double>();
      EXPECT_NEAR(x, y, 1e-9 * std::max(1.0, std::abs(y))) << species << " " << key;
      differs_from_constant = std::max(differs_from_constant,
                                       std::abs(x - c[species][key].get<double>()) / std::abs(x));
    }
  EXPECT_GT(differs_from_constant, 1e-3);

  const auto missing =
      run(dir, "missing", mesh, "  mesh_fields: [height]\n  diffusion_scale: height\n");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("sphere_width.vtp"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("'height'"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("width"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(dir / "missing" / "summary.json"));
}

} // namespace
} // namespace texsim
