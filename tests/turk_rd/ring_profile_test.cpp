// measure_rings, the radial profile behind Turk's rosettes (dark spots around a lighter centre):
// on a flat square of cells with three discs as regions, marks that form an annulus at the discs'
// edges cover the rim and none of the centre and every angular sector; marks filling a small
// central disc cover the centre and no rim; one mark beside the centre covers one or two sectors.
// The bins match a direct computation from the cells, at any rank count; regions of fewer than 8
// cells are left out.
#include "geom/generators.hpp"
#include "pipelines/turk_rd/ring_profile.hpp"
#include "square_cells.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <array>
#include <cmath>
#include <numbers>

namespace texsim::pipelines::turk_rd {
namespace {

const std::array<geom::Vec3, 3> kCentres = {geom::Vec3(0.25, 0.25, 0), geom::Vec3(0.72, 0.3, 0),
                                            geom::Vec3(0.45, 0.72, 0)};
constexpr double kRadius = 0.15;

struct Square : test::SquareCells {
  /// Index of the disc holding p, or -1.
  static int disc(const geom::Vec3& p) {
    for (int d = 0; d < 3; ++d)
      if ((p - kCentres[d]).norm() < kRadius)
        return d;
    return -1;
  }
  /// Per owned cell: in a disc, and `mark(p, centre)`.
  template <class Mark> RingProfile measure(Mark mark, bool tiny_region = false) const {
    std::vector<char> in_region, marked;
    for (std::int32_t i = 0; i < cells.owned_count(); ++i) {
      const geom::Vec3& p = cells.points()[i].position;
      const int d = disc(p);
      in_region.push_back(d >= 0 || (tiny_region && (p - geom::Vec3(0.9, 0.9, 0)).norm() < 0.01));
      marked.push_back(d >= 0 && mark(p, kCentres[d]));
    }
    return measure_rings(comm, cells, in_region, marked);
  }
};

TEST(RingProfile, AnnulusCoversTheRimAndEverySectorNotTheCentre) {
  const Square square;
  const auto ring = square.measure(
      [](const geom::Vec3& p, const geom::Vec3& c) { return (p - c).norm() > 0.8 * kRadius; });
  EXPECT_EQ(ring.regions, 3);
  EXPECT_EQ(ring.centre_marked, 0.0);
  EXPECT_GT(ring.rim_marked, 0.5);
  EXPECT_EQ(ring.rim_sectors_marked, 1.0);

  const auto centre = square.measure(
      [](const geom::Vec3& p, const geom::Vec3& c) { return (p - c).norm() < 0.3 * kRadius; });
  EXPECT_GT(centre.centre_marked, 0.2);
  EXPECT_EQ(centre.rim_marked, 0.0);
  EXPECT_EQ(centre.rim_sectors_marked, 0.0);

  const auto beside = square.measure([](const geom::Vec3& p, const geom::Vec3& c) {
    return (p - (c + geom::Vec3(0.85 * kRadius, 0, 0))).norm() < 0.1 * kRadius;
  });
  EXPECT_GT(beside.rim_sectors_marked, 0.0);
  EXPECT_LE(beside.rim_sectors_marked, 2.0 / 8.0);
}

TEST(RingProfile, BinsMatchADirectComputationAndSmallRegionsAreLeftOut) {
  const Square square;
  const auto mark = [](const geom::Vec3& p, const geom::Vec3& c) {
    return p.x() + 0.3 * p.y() > c.x() + 0.3 * c.y(); // half of each disc
  };
  // Direct: per disc the area-weighted centre and sqrt(area / pi), then the bins.
  std::array<double, 12> sums{}; // per disc: area, x, y, z
  const auto& cells = square.cells;
  for (std::int32_t i = 0; i < cells.owned_count(); ++i) {
    const geom::Vec3& p = cells.points()[i].position;
    const int d = Square::disc(p);
    if (d < 0)
      continue;
    const double a = cells.areas()[i];
    sums[4 * d] += a;
    for (int c = 0; c < 3; ++c)
      sums[4 * d + 1 + c] += a * p[c];
  }
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), 12, MPI_DOUBLE, MPI_SUM, square.comm.raw);
  std::array<double, 2 * kRingBins> bins{}; // area, marked area
  for (std::int32_t i = 0; i < cells.owned_count(); ++i) {
    const geom::Vec3& p = cells.points()[i].position;
    const int d = Square::disc(p);
    if (d < 0)
      continue;
    const geom::Vec3 centre(sums[4 * d + 1], sums[4 * d + 2], sums[4 * d + 3]);
    const double r = (p - centre / sums[4 * d]).norm() / std::sqrt(sums[4 * d] / std::numbers::pi);
    const int bin = std::min(int(r / 0.25), kRingBins - 1);
    bins[bin] += cells.areas()[i];
    if (mark(p, kCentres[d]))
      bins[kRingBins + bin] += cells.areas()[i];
  }
  MPI_Allreduce(MPI_IN_PLACE, bins.data(), 2 * kRingBins, MPI_DOUBLE, MPI_SUM, square.comm.raw);
  const auto profile = square.measure(mark, /*tiny_region=*/true);
  EXPECT_EQ(profile.regions, 3) << "the region of a cell or two is not measured";
  for (int b = 0; b < kRingBins; ++b)
    EXPECT_NEAR(profile.marked_by_radius[b], bins[b] > 0 ? bins[kRingBins + b] / bins[b] : 0.0,
                1e-12)
        << "bin " << b;
}

} // namespace
} // namespace texsim::pipelines::turk_rd
