// stripes_across_axis on a flat square of 8000 cells: stripes u = sin(2 pi 6 x) run straight
// across the x axis (share 1 within the least-squares gradients' error) and along the y axis (0);
// stripes at 45 degrees give 1/2, as a pattern without a direction does; an axis normal to the
// square leaves no cell to measure. The same value at 1, 2 and 3 ranks (reproducible sums).
#include "geom/generators.hpp"
#include "pipelines/turk_rd/stripe_direction.hpp"
#include "square_cells.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

namespace texsim::pipelines::turk_rd {
namespace {

struct Square : test::SquareCells {
  double across(const std::function<double(const geom::Vec3&)>& pattern,
                const geom::Vec3& axis) const {
    return stripes_across_axis(comm, cells, at_cells<double>(pattern), axis);
  }
};

TEST(StripeDirection, StripesAcrossAlongAndDiagonalToTheAxis) {
  const Square square;
  const double k = 2 * std::numbers::pi * 6;
  const auto across_x = [k](const geom::Vec3& p) { return std::sin(k * p.x()); };
  EXPECT_GT(square.across(across_x, geom::Vec3(1, 0, 0)), 0.97);
  EXPECT_LT(square.across(across_x, geom::Vec3(0, 2, 0)), 0.03);
  const auto diagonal = [k](const geom::Vec3& p) { return std::sin(k * (p.x() + p.y())); };
  EXPECT_NEAR(square.across(diagonal, geom::Vec3(1, 0, 0)), 0.5, 0.03);
  const auto spots = [k](const geom::Vec3& p) { return std::sin(k * p.x()) * std::sin(k * p.y()); };
  EXPECT_NEAR(square.across(spots, geom::Vec3(1, 0, 0)), 0.5, 0.05);
  EXPECT_EQ(square.across(across_x, geom::Vec3(0, 0, 1)), 0.0) << "no tangent part anywhere";
}

} // namespace
} // namespace texsim::pipelines::turk_rd
