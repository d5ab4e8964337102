// fem_rd.mesh_fields: the diffusion tensor's scale and direction read from point arrays of the
// mesh file. A sphere file holds, at its own vertices, rate = 1 + 3 (z > 0) and the parallels'
// direction (tx, ty, tz) = (-y, x, 0): on the same vertices the tensors equal those of the same
// formulas of position (up to the round-off of the closest-point interpolation), a heat run
// gives the same bump heights, and through the binary at 2 ranks the mesh-field config reproduces
// the formula config's summary (the distributed path: ghosts sampled on each rank). Configs
// that cannot use their mesh fields are refused, and leave the output directory free for the
// corrected config.
#include "geom/distributed_mesh.hpp"
#include "geom/distributed_mesh_fields.hpp"
#include "geom/generators.hpp"
#include "par/global_range.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"
#include "support/vtp_file.hpp"
#include "test_models.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace texsim::pipelines::fem_rd {
namespace {
namespace fs = std::filesystem;

constexpr int kLevel = 4;

/// The sphere of the solver's mesh with rate and direction arrays, written by rank 0.
fs::path sphere_file(const par::Comm& comm) {
  const auto path = texsim::test::scratch_dir("fem_rd_mesh_field_diffusion") / "sphere.vtp";
  if (comm.is_root()) {
    const auto mesh = geom::icosphere(kLevel, 1.0);
    std::vector<double> rate, tx, ty, tz;
    for (const auto& p : mesh.positions) {
      rate.push_back(1 + 3 * (p.z() > 0));
      tx.push_back(-p.y());
      ty.push_back(p.x());
      tz.push_back(0);
    }
    texsim::test::write_vtp(path, mesh, {{"rate", rate}, {"tx", tx}, {"ty", ty}, {"tz", tz}});
  }
  comm.barrier();
  return path;
}

DiffusionFieldSettings from_formulas() {
  return {{"-y", "x", "0"}, 4.0, 1.0, "1 + 3 * (z > 0)", {}, {}, {}};
}

DiffusionFieldSettings from_mesh_fields(const fs::path& file) {
  DiffusionFieldSettings settings{{"tx", "ty", "tz"},         4.0, 1.0, "rate", {},
                                  {"rate", "tx", "ty", "tz"}, {}};
  geom::MeshSource source;
  source.file = file;
  settings.mesh_field_values =
      std::make_shared<geom::DistributedMeshFields>(par::world(), source, settings.mesh_fields);
  return settings;
}

TEST(MeshFieldDiffusion, TensorsEqualThoseOfTheSameFormulas) {
  const par::Comm comm = par::world();
  const auto file = sphere_file(comm);
  const geom::DistributedMesh mesh(comm, geom::icosphere(kLevel, 1.0),
                                   geom::PartitionMethod::kMorton);
  const std::size_t count = std::size_t(mesh.owned_count()) + mesh.ghosts().size();
  const DiffusionField formulas(from_formulas(), {"u"});
  const DiffusionField fields(from_mesh_fields(file), {"u"});
  const std::vector<double> zero(count, 0.0), one(count, 1.0);
  const auto expected = formulas.tensors(mesh.mesh(), count, {std::span<const double>(zero)});
  fields.update_mesh_fields(mesh.mesh());
  const auto got = fields.tensors(mesh.mesh(), count, {std::span<const double>(zero)});
  ASSERT_EQ(got.size(), expected.size());
  double worst = 0;
  for (std::size_t k = 0; k < got.size(); ++k)
    worst = std::max(worst, std::abs(got[k] - expected[k]));
  EXPECT_LT(worst, 1e-9) << "largest tensor entry difference";
  // A field that reads a species and a mesh field: u scales the rate where rate says.
  DiffusionFieldSettings both = from_mesh_fields(file);
  both.scale = "rate * (1 + u)";
  const DiffusionField mixed(both, {"u"});
  mixed.update_mesh_fields(mesh.mesh());
  const auto doubled = mixed.tensors(mesh.mesh(), count, {std::span<const double>(one)});
  for (std::size_t k = 0; k < got.size(); ++k)
    ASSERT_NEAR(doubled[k], 2 * got[k], 1e-12);
}

/// Bump heights of a heat run (as in variable_diffusion_test) under the tensor `field`.
std::array<double, 2> bump_heights(const DiffusionFieldSettings& field) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(kLevel, 1.0),
                                   geom::PartitionMethod::kMorton);
  const test::HeatModel model([](double x, double y, double z) {
    return std::exp(-8 * (x * x + y * y + (z - 1) * (z - 1))) +
           std::exp(-8 * (x * x + y * y + (z + 1) * (z + 1)));
  });
  ReactionDiffusionSolver solver(comm, mesh, model, {0.002, false, 1e-12}, field);
  for (int n = 0; n < 20; ++n)
    solver.step(n);
  std::vector<double> upper, lower;
  const auto u = solver.local_values(0);
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v)
    (mesh.mesh().positions[std::size_t(v)].z() > 0 ? upper : lower).push_back(u[std::size_t(v)]);
  return {par::global_range(comm, upper).max, par::global_range(comm, lower).max};
}

TEST(MeshFieldDiffusion, HeatRunMatchesTheFormulaRun) {
  const auto file = sphere_file(par::world());
  const auto formulas = bump_heights(from_formulas());
  const auto fields = bump_heights(from_mesh_fields(file));
  EXPECT_NEAR(fields[0], formulas[0], 1e-8);
  EXPECT_NEAR(fields[1], formulas[1], 1e-8);
  EXPECT_LT(fields[0], fields[1] - 0.05) << "the larger rate (upper half) flattens its bump first";
}

/// Runs fem_rd through the binary at 2 ranks on the sphere file with `diffusion` lines.
texsim::test::CommandOutcome run(const fs::path& dir, const std::string& name, const fs::path& file,
                                 const std::string& diffusion) {
  const fs::path config = dir / (name + ".yaml");
  std::ofstream(config) << "pipeline: fem_rd\nseed: 3\noutput: {dir: " << (dir / name).string()
                        << ", every: 40}\nfem_rd:\n  mesh: {file: " << file.string()
                        << ", scale: 6}\n  time: {dt: 0.5, steps: 40}\n"
                        << "  model: {type: fitzhugh_nagumo}\n"
                        << diffusion;
  return texsim::test::run_command(texsim::test::texsim_under_mpirun(2) + " " + config.string() +
                                   " --quiet");
}

nlohmann::json species_metrics(const fs::path& out) {
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in)["metrics"]["species"];
}

TEST(MeshFieldDiffusion, BinaryRunMatchesTheFormulaRunAndRefusesUnusableFields) {
  const par::Comm comm = par::world();
  const auto file = sphere_file(comm);
  const auto dir = file.parent_path();
  const auto formulas =
      run(dir, "formulas", file,
          "  diffusion: {direction: [\"-y\", x, \"0\"], along: 4, scale: \"1 + 3 * (z > 0)\"}\n");
  ASSERT_EQ(formulas.exit_code, 0) << formulas.output;
  const auto fields = run(dir, "fields", file,
                          "  mesh_fields: [rate, tx, ty, tz]\n"
                          "  diffusion: {direction: [tx, ty, tz], along: 4, scale: rate}\n");
  ASSERT_EQ(fields.exit_code, 0) << fields.output;
  const auto a = species_metrics(dir / "formulas"), b = species_metrics(dir / "fields");
  for (const char* species : {"a", "b"}) { // FitzHugh-Nagumo's
    SCOPED_TRACE(species);
    for (const char* key : {"min", "max", "final_integral"})
      EXPECT_NEAR(b[species][key].get<double>(), a[species][key].get<double>(),
                  1e-9 * (1 + std::abs(a[species][key].get<double>())))
          << key;
    EXPECT_NEAR(b[species]["stripes"]["angle_to_field_deg"].get<double>(),
                a[species]["stripes"]["angle_to_field_deg"].get<double>(), 1e-3);
  }

  const auto without_diffusion = run(dir, "without_diffusion", file, "  mesh_fields: [rate]\n");
  EXPECT_EQ(without_diffusion.exit_code, 2) << without_diffusion.output;
  EXPECT_NE(without_diffusion.output.find("fem_rd.mesh_fields"), std::string::npos)
      << without_diffusion.output;
  const auto missing =
      run(dir, "missing", file, "  mesh_fields: [width]\n  diffusion: {scale: width}\n");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("sphere.vtp"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("rate"), std::string::npos)
      << "the message lists the arrays the file has: " << missing.output;
  // The refused run wrote nothing: the corrected config runs in the same directory.
  const auto corrected =
      run(dir, "missing", file, "  mesh_fields: [rate]\n  diffusion: {scale: rate}\n");
  EXPECT_EQ(corrected.exit_code, 0) << corrected.output;
}

} // namespace
} // namespace texsim::pipelines::fem_rd
