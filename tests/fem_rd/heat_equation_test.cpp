// The FEM solver against the heat equation on the unit sphere: spherical harmonics decay as
// exp(-l(l+1) t), with second-order convergence; diffusion conserves the integral.
#include "geom/generators.hpp"
#include "par/comm.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"
#include "test_models.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace texsim::pipelines::fem_rd {
namespace {

// Degree-2 zonal harmonic, eigenvalue l(l+1) = 6 of the unit sphere's Laplace-Beltrami operator.
double harmonic(double, double, double z) {
  return 3 * z * z - 1;
}

// Amplitude of the harmonic in u: (u, Y) / (Y, Y), each integral taken of the P1 interpolant of
// the product with the solver's mass matrix (second-order accurate, like the method itself).
double decayed_amplitude(int level, double end_time, int steps) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(level), geom::PartitionMethod::kMorton);
  const test::HeatModel model(harmonic);
  ReactionDiffusionSolver solver(comm, mesh, model, {end_time / steps, false, 1e-12});
  for (int n = 0; n < steps; ++n)
    solver.step(n * end_time / steps);
  std::vector<double> u(solver.local_values(0).begin(),
                        solver.local_values(0).begin() + mesh.owned_count());
  std::vector<double> product(u.size()), square(u.size());
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v) {
    const auto& p = mesh.mesh().positions[v];
    const double y = harmonic(p.x(), p.y(), p.z());
    product[v] = u[v] * y;
    square[v] = y * y;
  }
  solver.set_owned_values(0, product);
  const double uy = solver.integral(0);
  solver.set_owned_values(0, square);
  const double yy = solver.integral(0);
  return uy / yy;
}

TEST(HeatEquation, HarmonicDecaysAsExpMinusSixTAtSecondOrder) {
  const double end_time = 0.05;
  const double exact = std::exp(-6.0 * end_time);
  std::vector<double> errors;
  // Time step proportional to h^2 so backward Euler's O(dt) error is O(h^2) too.
  for (int level = 3, steps = 8; level <= 5; ++level, steps *= 4)
    errors.push_back(std::abs(decayed_amplitude(level, end_time, steps) - exact));
  for (std::size_t k = 0; k + 1 < errors.size(); ++k) {
    const double order = std::log2(errors[k] / errors[k + 1]);
    EXPECT_GT(order, 1.7) << "errors " << errors[k] << " -> " << errors[k + 1];
    EXPECT_LT(order, 2.5) << "errors " << errors[k] << " -> " << errors[k + 1];
  }
  EXPECT_LT(errors.back(), 2e-3);
}

TEST(HeatEquation, PureDiffusionConservesTheIntegral) {
  const par::Comm comm = par::world();
  const auto surface = geom::noisy(geom::icosphere(4), 0.02, 3);
  const geom::DistributedMesh mesh(comm, surface, geom::PartitionMethod::kScotch);
  const test::HeatModel model(
      [](double x, double y, double z) { return std::sin(3 * x) + y * y * z + 2.0; });
  ReactionDiffusionSolver solver(comm, mesh, model, {0.01, false, 1e-13});
  const double before = solver.integral(0);
  for (int n = 0; n < 20; ++n)
    solver.step(0.01 * n);
  EXPECT_NEAR(solver.integral(0) / before, 1.0, 1e-10);
}

TEST(HeatEquation, LumpedMassAlsoConserves) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::torus(1.0, 0.3, 40, 16),
                                   geom::PartitionMethod::kMorton);
  const test::HeatModel model([](double x, double, double) { return x > 0 ? 1.0 : 0.0; });
  ReactionDiffusionSolver solver(comm, mesh, model, {0.02, true, 1e-13});
  const double before = solver.integral(0);
  for (int n = 0; n < 20; ++n)
    solver.step(0.02 * n);
  EXPECT_NEAR(solver.integral(0) / before, 1.0, 1e-10);
}

} // namespace
} // namespace texsim::pipelines::fem_rd
