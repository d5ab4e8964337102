// Fig. 3 of Bajaj, Zhang, Xu: the Turing system (eqs. 12-15) forms spots on a sphere, and the
// number of spots grows with s. Spots are counted as connected regions above the mean.
#include "core/config.hpp"
#include "geom/generators.hpp"
#include "pipelines/fem_rd/pattern_regions.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"

#include <gtest/gtest.h>

namespace texsim::pipelines::fem_rd {
namespace {

int spots_after(double s, int steps) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(4, 12.0), geom::PartitionMethod::kMorton);
  auto config = ConfigDocument::parse("type: turing_spots\ns: " + std::to_string(s), "test");
  const auto model = rd::make_reaction_model(config.root(), 1);
  ReactionDiffusionSolver solver(comm, mesh, *model, {1.0, false, 1e-10});
  for (int n = 0; n < steps; ++n)
    solver.step(n);
  return count_regions_above_mean(mesh, solver.local_values(0).first(mesh.owned_count())).regions;
}

TEST(TuringSpots, SpotCountGrowsWithS) {
  const int few = spots_after(0.025, 800);
  const int many = spots_after(0.05, 800);
  // A pattern formed (not a uniform state, not noise), and it is finer for the larger s.
  EXPECT_GE(few, 10);
  EXPECT_LE(many, 200);
  EXPECT_GT(many, few * 3 / 2) << "s = 0.025: " << few << " spots, s = 0.05: " << many;
}

} // namespace
} // namespace texsim::pipelines::fem_rd
