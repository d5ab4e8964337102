// fem_rd.diffusion: diffusion faster along a tangent field stretches the pattern along it. The
// FitzHugh-Nagumo domains of Fig. 4 grown on a sphere under C0C1 (across I + (along - across)
// t t^T) run along t: along the parallels for t = (-y, x, 0), along the meridians for
// t = (0, 0, 1) projected, both within 10 degrees (structure tensor of grad a in each
// triangle's (t, n x t) frame), while the same run with isotropic diffusion has no direction.
#include "core/config.hpp"
#include "geom/generators.hpp"
#include "pipelines/fem_rd/pattern_orientation.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"

#include <gtest/gtest.h>

namespace texsim::pipelines::fem_rd {
namespace {

constexpr int kSteps = 300;

StripeOrientation grown(const std::array<std::string, 3>& direction, double along,
                        const DiffusionFieldSettings& measured_against) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(5, 20.0), geom::PartitionMethod::kMorton);
  auto config = ConfigDocument::parse("type: fitzhugh_nagumo\ns: 0.05", "test");
  const auto model = rd::make_reaction_model(config.root(), 1);
  ReactionDiffusionSolver solver(comm, mesh, *model,
                                 {.dt = 1.0, .lumped_mass = false, .rtol = 1e-10},
                                 DiffusionFieldSettings{direction, along, 1.0, "1", {}});
  for (int n = 0; n < kSteps; ++n)
    solver.step(n);
  return stripe_orientation(mesh, solver.local_values(0),
                            DiffusionField(measured_against, model->species()));
}

TEST(StripeAlignment, PatternsRunAlongTheFasterDirection) {
  const DiffusionFieldSettings parallels{{"-y", "x", "0"}, 1.0, 1.0, "1", {}};
  const DiffusionFieldSettings meridians{{"0", "0", "1"}, 1.0, 1.0, "1", {}};
  const StripeOrientation along_parallels = grown(parallels.direction, 9.0, parallels);
  const StripeOrientation along_meridians = grown(meridians.direction, 9.0, meridians);
  const StripeOrientation isotropic = grown(parallels.direction, 1.0, parallels);
  EXPECT_LT(along_parallels.angle_to_field_deg, 10.0);
  EXPECT_LT(along_meridians.angle_to_field_deg, 10.0);
  EXPECT_GT(along_parallels.coherence, 2 * isotropic.coherence)
      << "isotropic coherence " << isotropic.coherence;
  EXPECT_GT(along_meridians.coherence, 2 * isotropic.coherence)
      << "isotropic coherence " << isotropic.coherence;
  std::printf("parallels: %.2f deg, coherence %.3f; meridians: %.2f deg, coherence %.3f; "
              "isotropic: %.2f deg, coherence %.3f\n",
              along_parallels.angle_to_field_deg, along_parallels.coherence,
              along_meridians.angle_to_field_deg, along_meridians.coherence,
              isotropic.angle_to_field_deg, isotropic.coherence);
}

} // namespace
} // namespace texsim::pipelines::fem_rd
