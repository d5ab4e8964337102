// The distributed solve on all ranks agrees with the same problem solved on one rank (each rank
// solves it alone on MPI_COMM_SELF) to the solver tolerance, for both partition methods.
#include "geom/generators.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"
#include "support/gather_by_id.hpp"
#include "test_models.hpp"

#include <gtest/gtest.h>

namespace texsim::pipelines::fem_rd {
namespace {

// Values after `steps` steps, in input-vertex order, on every rank.
std::vector<double> solve(const par::Comm& comm, const geom::TriangleMesh& surface,
                          geom::PartitionMethod method, int steps, FemBasis basis = FemBasis::kP1) {
  const geom::DistributedMesh mesh(comm, surface, method);
  const test::FisherModel model;
  RdOptions options{0.5, false, 1e-12};
  options.basis = basis;
  ReactionDiffusionSolver solver(comm, mesh, model, options);
  for (int n = 0; n < steps; ++n)
    solver.step(0.5 * n);
  return texsim::test::gather_by_id(comm, mesh.owned_input_ids(),
                                    solver.local_values(0).first(mesh.owned_count()));
}

par::Comm self() {
  par::Comm comm;
  comm.raw = MPI_COMM_SELF;
  return comm;
}

class RankAgreement : public ::testing::TestWithParam<geom::PartitionMethod> {};

TEST_P(RankAgreement, DistributedEqualsSerialToSolverTolerance) {
  const auto surface = geom::noisy(geom::icosphere(4, 5.0), 0.05, 9);
  const auto serial = solve(self(), surface, GetParam(), 15);
  const auto distributed = solve(par::world(), surface, GetParam(), 15);
  ASSERT_EQ(serial.size(), distributed.size());
  double largest = 0;
  for (std::size_t v = 0; v < serial.size(); ++v)
    largest = std::max(largest, std::abs(serial[v] - distributed[v]));
  EXPECT_LT(largest, 1e-8);
  // The run did something: values moved away from the uniform random start.
  double mean = 0;
  for (double u : distributed)
    mean += u / double(distributed.size());
  EXPECT_GT(mean, 0.6);
}

TEST(RankAgreement, LoopBasisDistributedEqualsSerialToSolverTolerance) {
  // Loop's functions reach three rings out: every rank's rows need its whole halo; on the open
  // surface a part's border must not be mistaken for the surface's boundary.
  for (const auto& surface :
       {geom::noisy(geom::icosphere(3, 5.0), 0.05, 9), test::sphere_without_its_cap()}) {
    const auto serial = solve(self(), surface, geom::PartitionMethod::kScotch, 10, FemBasis::kLoop);
    const auto distributed =
        solve(par::world(), surface, geom::PartitionMethod::kScotch, 10, FemBasis::kLoop);
    ASSERT_EQ(serial.size(), distributed.size());
    double largest = 0;
    for (std::size_t v = 0; v < serial.size(); ++v)
      largest = std::max(largest, std::abs(serial[v] - distributed[v]));
    EXPECT_LT(largest, 1e-8);
  }
}

INSTANTIATE_TEST_SUITE_P(Partitions, RankAgreement,
                         ::testing::Values(geom::PartitionMethod::kMorton,
                                           geom::PartitionMethod::kScotch));

} // namespace
} // namespace texsim::pipelines::fem_rd
