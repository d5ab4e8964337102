#include "vol/periodic_noise.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace texsim::vol {
namespace {

TEST(PeriodicGradientNoise, PeriodicZeroAtLatticePointsAndBounded) {
  const PeriodicGradientNoise noise(42, 0, 5);
  double max_abs = 0.0;
  for (int s = 0; s < 200; ++s) {
    const double x = 0.37 * s, y = 0.11 * s - 3.0, z = 0.23 * s + 1.5;
    const double v = noise(x, y, z);
    EXPECT_NEAR(noise(x + 5, y, z), v, 1e-12);
    EXPECT_NEAR(noise(x, y - 10, z), v, 1e-12);
    EXPECT_NEAR(noise(x, y, z + 15), v, 1e-12);
    max_abs = std::max(max_abs, std::abs(v));
  }
  EXPECT_LE(max_abs, 1.0);
  EXPECT_GT(max_abs, 0.2); // not degenerate
  EXPECT_EQ(noise(2, 3, -4), 0.0);
}

TEST(PeriodicGradientNoise, SeedsAndOctavesGiveIndependentLattices) {
  const PeriodicGradientNoise a(1, 0, 4), b(2, 0, 4), c(1, 1, 4);
  EXPECT_NE(a(0.5, 0.5, 0.5), b(0.5, 0.5, 0.5));
  EXPECT_NE(a(0.5, 0.5, 0.5), c(0.5, 0.5, 0.5));
  EXPECT_EQ(a(0.5, 0.5, 0.5), PeriodicGradientNoise(1, 0, 4)(0.5, 0.5, 0.5));
}

TEST(PeriodicFractalNoise, SumsArePeriodicInTileUnits) {
  const PeriodicFractalNoise noise(7, 3, 4);
  for (int s = 0; s < 50; ++s) {
    const double u = 0.0173 * s, v = 0.031 * s, w = 0.007 * s;
    EXPECT_NEAR(noise.fbm(u + 1, v, w - 1), noise.fbm(u, v, w), 1e-12);
    EXPECT_NEAR(noise.turbulence(u, v + 2, w), noise.turbulence(u, v, w), 1e-12);
    EXPECT_GE(noise.turbulence(u, v, w), 0.0);
  }
}

} // namespace
} // namespace texsim::vol
