// The patterns of Turk 1991 on cells spread over a surface: Turing's spot system forms round spots
// whose number grows with s (smaller spots), and Meinhardt's stripe system forms elongated regions,
// not spots. Regions are the connected cells above the mean; elongation is perimeter^2 / (4 pi A).
#include "core/config.hpp"
#include "geom/generators.hpp"
#include "pipelines/turk_rd/cell_rd_solver.hpp"
#include "pipelines/turk_rd/pattern_shapes.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>

namespace texsim::pipelines::turk_rd {
namespace {

PatternShapes pattern_after(const geom::TriangleMesh& mesh, std::int64_t cells_count,
                            const std::string& model_yaml, int steps,
                            const par::Comm& comm = par::world()) {
  geom::SurfaceCellsSettings settings;
  settings.count = cells_count;
  const geom::SurfaceCells cells(comm, geom::DistributedTriangles::from_replicated(comm, mesh), 4,
                                 settings);
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
  EXPECT_LT(large.median_aspect, 1.6); // round spots: principal axes about equal
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

TEST(TurkPatterns, AspectIsThePrincipalAxesRatioOfEachRegion) {
  // Values marking two regions on a flat square: a 0.6 x 0.1 bar and a disc of radius 0.12. The
  // measured aspects are the square roots of the eigenvalue ratios of the area-weighted cell
  // covariance computed here directly (so a tolerance for summation order only); the bar is about
  // 6, the disc about 1.
  const auto square = geom::plane(geom::Vec3(1, 1, 0), 40);
  const par::Comm comm = par::world();
  geom::SurfaceCellsSettings settings;
  settings.count = 6000;
  const geom::SurfaceCells cells(comm, geom::DistributedTriangles::from_replicated(comm, square), 4,
                                 settings);
  const auto in_bar = [](const geom::Vec3& p) {
    return std::abs(p.x() - 0.5) < 0.3 && std::abs(p.y() - 0.3) < 0.05;
  };
  const auto in_disc = [](const geom::Vec3& p) {
    return (p - geom::Vec3(0.5, 0.7, 0)).norm() < 0.12;
  };
  std::vector<double> values(std::size_t(cells.owned_count()));
  std::vector<double> moments(2 * 10, 0.0); // per region: area, 3 first, 6 second moments
  for (std::int32_t i = 0; i < cells.owned_count(); ++i) {
    const geom::Vec3& p = cells.points()[i].position;
    const int region = in_bar(p) ? 0 : in_disc(p) ? 1 : -1;
    values[i] = region >= 0 ? 1.0 : 0.0;
    if (region < 0)
      continue;
    const double a = cells.areas()[i];
    double* m = moments.data() + 10 * region;
    const double terms[10] = {a,
                              a * p.x(),
                              a * p.y(),
                              a * p.z(),
                              a * p.x() * p.x(),
                              a * p.x() * p.y(),
                              a * p.x() * p.z(),
                              a * p.y() * p.y(),
                              a * p.y() * p.z(),
                              a * p.z() * p.z()};
    for (int k = 0; k < 10; ++k)
      m[k] += terms[k];
  }
  MPI_Allreduce(MPI_IN_PLACE, moments.data(), int(moments.size()), MPI_DOUBLE, MPI_SUM, comm.raw);
  std::vector<double> expected;
  for (int region = 0; region < 2; ++region) {
    const double* m = moments.data() + 10 * region;
    const Eigen::Vector3d mean(m[1] / m[0], m[2] / m[0], m[3] / m[0]);
    Eigen::Matrix3d c;
    c << m[4], m[5], m[6], m[5], m[7], m[8], m[6], m[8], m[9];
    c = c / m[0] - mean * mean.transpose();
    const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c).eigenvalues();
    expected.push_back(std::sqrt(lambda[2] / lambda[1]));
  }
  const PatternShapes shapes = measure_pattern(comm, cells, values);
  ASSERT_EQ(shapes.regions, 2);
  std::sort(expected.begin(), expected.end());
  EXPECT_NEAR(expected[0], 1.0, 0.15);
  EXPECT_NEAR(expected[1], 6.0, 1.0);
  // Median of two: the larger; weighted by cells: the bar has about 0.06 / (pi 0.0144) of the
  // disc's.
  EXPECT_NEAR(shapes.median_aspect, expected[1], 1e-9 * expected[1]);
  EXPECT_GT(shapes.weighted_aspect, expected[0]);
  EXPECT_LT(shapes.weighted_aspect, expected[1]);
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
  EXPECT_EQ(split.median_aspect, serial.median_aspect);
  EXPECT_EQ(split.weighted_aspect, serial.weighted_aspect);
}

} // namespace
} // namespace texsim::pipelines::turk_rd
