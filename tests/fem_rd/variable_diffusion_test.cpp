// fem_rd.diffusion.scale read as a function of position and of the species' values: the heat
// equation with rate 1 + u^2 (u in [0, 1]) keeps the integral of u (1^T K = 0 for any tensor)
// and flattens a bump faster than rate 1 and slower than rate 2, at every rank count alike;
// a rate that is larger in the upper half (scale 1 + 3 (z > 0)) flattens the upper bump first.
#include "geom/generators.hpp"
#include "par/global_range.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"
#include "test_models.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace texsim::pipelines::fem_rd {
namespace {

constexpr int kSteps = 20;

/// Bumps of height 1 at the poles (0, 0, +-1) of the unit sphere.
double bumps(double x, double y, double z) {
  return std::exp(-8 * (x * x + y * y + (z - 1) * (z - 1))) +
         std::exp(-8 * (x * x + y * y + (z + 1) * (z + 1)));
}

struct HeatRun {
  double initial_integral, final_integral, upper_max, lower_max;
};

HeatRun heat(const std::string& scale) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(4, 1.0), geom::PartitionMethod::kMorton);
  const test::HeatModel model(bumps);
  ReactionDiffusionSolver solver(comm, mesh, model, {0.002, false, 1e-12},
                                 DiffusionFieldSettings{{"0", "0", "0"}, 1.0, 1.0, scale, {}});
  HeatRun run{solver.integral(0), 0, 0, 0};
  for (int n = 0; n < kSteps; ++n)
    solver.step(n);
  run.final_integral = solver.integral(0);
  std::vector<double> upper, lower;
  const auto u = solver.local_values(0);
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v)
    (mesh.mesh().positions[std::size_t(v)].z() > 0 ? upper : lower).push_back(u[std::size_t(v)]);
  run.upper_max = par::global_range(comm, upper).max;
  run.lower_max = par::global_range(comm, lower).max;
  return run;
}

TEST(VariableDiffusion, RateOfTheSpeciesValuesConservesAndLiesBetweenItsBounds) {
  const HeatRun slow = heat("1"), fast = heat("2"), nonlinear = heat("1 + u^2");
  EXPECT_NEAR(nonlinear.final_integral, nonlinear.initial_integral,
              1e-9 * nonlinear.initial_integral);
  EXPECT_LT(nonlinear.upper_max, slow.upper_max - 1e-3);
  EXPECT_GT(nonlinear.upper_max, fast.upper_max + 1e-3);
  std::printf("bump height after %d steps: rate 1 %.4f, 1 + u^2 %.4f, 2 %.4f\n", kSteps,
              slow.upper_max, nonlinear.upper_max, fast.upper_max);
}

TEST(VariableDiffusion, RateOfPositionActsWhereItIsLarger) {
  const HeatRun run = heat("1 + 3 * (z > 0)");
  EXPECT_NEAR(run.final_integral, run.initial_integral, 1e-9 * run.initial_integral);
  EXPECT_LT(run.upper_max, run.lower_max - 0.05)
      << "upper " << run.upper_max << ", lower " << run.lower_max;
}

} // namespace
} // namespace texsim::pipelines::fem_rd
