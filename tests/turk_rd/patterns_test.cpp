// The patterns of Turk 1991 on cells spread over a surface: Turing's spot system forms round spots
// whose number grows with s (smaller spots), and Meinhardt's stripe system forms elongated regions,
// not spots. Regions are the connected cells above the mean; elongation is perimeter^2 / (4 pi A).
#include "core/config.hpp"
#include "geom/generators.hpp"
#include "pipelines/turk_rd/cell_rd_solver.hpp"
#include "pipelines/turk_rd/pattern_shapes.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

namespace texsim::pipelines::turk_rd {
namespace {

PatternShapes pattern_after(const geom::TriangleMesh& mesh, std::int64_t cells_count,
                            const std::string& model_yaml, int steps,
                            const par::Comm& comm = par::world()) {
  geom::SurfaceCellsSettings settings;
  settings.count = cells_count;
  const geom::SurfaceCells cells(comm, mesh, geom::MeshTopology(mesh), 4, settings);
  auto config = ConfigDocument::parse(model_yaml, "test");
  const auto model = rd::make_reaction_model(config.root(), 4);
  const std::vector<double> scale(std::size_t(cells.owned_count()), 1.0);
  CellRdSolver solver(comm, cells, *model, scale, 1.0);
  for (int n = 0; n < steps; ++n)
    solver.step(n);
  return measure_pattern(comm, cells, solver.owned_values(0));
}

TEST(TurkPatterns, SpotCountRisesAsSpotSizeFalls) {
  // Turk's s sets the spot size: larger s, smaller spots, more of them.
  const auto sphere = geom::icosphere(4);
  const auto large = pattern_after(sphere, 2500, "type: turing_spots\ns: 0.025\n", 4000);
  const auto small = pattern_after(sphere, 2500, "type: turing_spots\ns: 0.05\n", 4000);
  EXPECT_GE(large.regions, 15) << "no spot pattern formed";
  EXPECT_GT(small.regions, large.regions * 3 / 2)
      << "s = 0.025: " << large.regions << " spots, s = 0.05: " << small.regions;
  // Spots are round: a disc has elongation 1; ragged cell boundaries add a little.
  EXPECT_LT(large.median_elongation, 2.5);
  EXPECT_LT(small.median_elongation, 2.5);
}

TEST(TurkPatterns, StripeSystemMakesStripesNotSpots) {
  const auto torus = geom::torus(1.0, 0.4, 96, 40);
  const auto stripes = pattern_after(torus, 2500, "type: meinhardt_stripes\n", 15000);
  const auto spots = pattern_after(torus, 2500, "type: turing_spots\ns: 0.05\n", 4000);
  EXPECT_GE(stripes.regions, 2) << "no stripe pattern formed";
  // Measured: stripes 22.6 (6 regions), spots 1.56 (117 regions).
  EXPECT_GT(stripes.weighted_elongation, 4.0);
  EXPECT_GT(stripes.weighted_elongation, 2.0 * spots.weighted_elongation)
      << "stripes " << stripes.weighted_elongation << ", spots " << spots.weighted_elongation;
}

TEST(TurkPatterns, ShapesAreTheSameBitsOnAnyRankCount) {
  // Each rank measures its own cells; stripes cross every partition. The cells and their values
  // are the same on any rank count, and so must the figures be, to the bit.
  const auto torus = geom::torus(1.0, 0.4, 96, 40);
  const std::string stripes = "type: meinhardt_stripes\n";
  const auto split = pattern_after(torus, 2500, stripes, 6000);
  if (par::world().rank != 0)
    return;
  const auto serial = pattern_after(torus, 2500, stripes, 6000, par::Comm{MPI_COMM_SELF, 0, 1});
  EXPECT_GE(serial.regions, 2) << "no stripe pattern formed";
  EXPECT_EQ(split.regions, serial.regions);
  EXPECT_EQ(split.mean_cells, serial.mean_cells);
  EXPECT_EQ(split.median_elongation, serial.median_elongation);
  EXPECT_EQ(split.max_elongation, serial.max_elongation);
  EXPECT_EQ(split.weighted_elongation, serial.weighted_elongation);
}

} // namespace
} // namespace texsim::pipelines::turk_rd
