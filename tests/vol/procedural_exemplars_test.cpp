#include "vol/procedural_exemplars.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace texsim::vol {
namespace {

using Generator = std::function<RgbGrid(int, std::uint64_t)>;

struct Case {
  const char* name;
  Generator make;
};

const Case kCases[] = {
    {"marble", [](int n, std::uint64_t s) { return marble_exemplar(n, s); }},
    {"wood", [](int n, std::uint64_t s) { return wood_exemplar(n, s); }},
    {"particles", [](int n, std::uint64_t s) { return particle_exemplar(n, s); }},
    {"bricks", [](int n, std::uint64_t s) { return brick_exemplar(n, s); }},
};

double colour_distance(const img::Rgb& a, const img::Rgb& b) {
  return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b);
}

/// Mean colour difference between voxels a and a + 1 along `axis`, over interior pairs
/// (a + 1 < n) or over the wrap-around pairs (n - 1, 0) only.
double mean_step(const RgbGrid& grid, int axis, bool across_seam) {
  const int n = grid.dims().nx;
  double sum = 0.0;
  std::size_t count = 0;
  for (int p = 0; p < n; ++p) {
    for (int q = 0; q < n; ++q) {
      for (int a = across_seam ? n - 1 : 0; a < (across_seam ? n : n - 1); ++a) {
        const int i[3] = {axis == 0 ? a : p, axis == 1 ? a : (axis == 0 ? p : q),
                          axis == 2 ? a : q};
        const int d[3] = {axis == 0, axis == 1, axis == 2};
        sum += colour_distance(grid.at(i[0], i[1], i[2]),
                               grid.periodic(i[0] + d[0], i[1] + d[1], i[2] + d[2]));
        ++count;
      }
    }
  }
  return sum / static_cast<double>(count);
}

TEST(ProceduralExemplars, DeterministicPerSeedAndDifferentAcrossSeeds) {
  for (const Case& c : kCases) {
    const RgbGrid a = c.make(24, 5);
    EXPECT_EQ(a, c.make(24, 5)) << c.name;
    EXPECT_NE(a, c.make(24, 6)) << c.name;
    EXPECT_EQ(a.dims(), (Dims{24, 24, 24})) << c.name;
  }
}

TEST(ProceduralExemplars, SeamsAreNoRougherThanTheInterior) {
  for (const Case& c : kCases) {
    const RgbGrid grid = c.make(48, 3);
    for (int axis = 0; axis < 3; ++axis) {
      const double interior = mean_step(grid, axis, false);
      const double seam = mean_step(grid, axis, true);
      EXPECT_GT(interior, 0.0) << c.name;
      EXPECT_LT(seam, 2.0 * interior + 1e-6) << c.name << " axis " << axis;
    }
  }
}

TEST(ProceduralExemplars, DoubleResolutionSampledAtEvenVoxelsIsTheSameTile) {
  for (const Case& c : kCases) {
    const RgbGrid coarse = c.make(16, 8);
    const RgbGrid fine = c.make(32, 8);
    std::size_t differ = 0;
    for (int k = 0; k < 16; ++k) {
      for (int j = 0; j < 16; ++j) {
        for (int i = 0; i < 16; ++i) {
          differ += colour_distance(coarse.at(i, j, k), fine.at(2 * i, 2 * j, 2 * k)) > 1e-5f;
        }
      }
    }
    EXPECT_EQ(differ, 0u) << c.name;
  }
}

TEST(ProceduralExemplars, ColoursStayInTheUnitRange) {
  for (const Case& c : kCases) {
    const RgbGrid grid = c.make(32, 1);
    for (const img::Rgb& v : grid.data()) {
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_GE(v[ch], 0.0f) << c.name;
        ASSERT_LE(v[ch], 1.0f) << c.name;
      }
    }
  }
}

TEST(ProceduralExemplars, ParticleCoverageNearTarget) {
  ParticleParams params;
  const RgbGrid grid = particle_exemplar(64, 11, params);
  std::size_t covered = 0;
  for (const img::Rgb& v : grid.data()) {
    covered += v == params.background ? 0 : 1;
  }
  const double fraction = static_cast<double>(covered) / static_cast<double>(grid.size());
  EXPECT_GT(fraction, params.target_coverage - 0.05);
  EXPECT_LT(fraction, params.target_coverage + 0.05);
}

TEST(ProceduralExemplars, BrickMortarFractionMatchesTheJointGeometry) {
  BrickParams params;
  params.mortar = 0.04;
  const RgbGrid grid = brick_exemplar(64, 2, params);
  std::size_t mortar = 0;
  for (const img::Rgb& v : grid.data()) {
    // Mortar is light grey, bricks are red: the blue channel separates them.
    mortar += v.b > 0.5f ? 1 : 0;
  }
  // Brick interiors along each axis keep (size - mortar) / size of the tile.
  const double keep = (1.0 - params.mortar * params.bricks_x) *
                      (1.0 - params.mortar * params.rows_y) *
                      (1.0 - params.mortar * params.layers_z);
  const double fraction = static_cast<double>(mortar) / static_cast<double>(grid.size());
  EXPECT_NEAR(fraction, 1.0 - keep, 0.06);
}

TEST(ProceduralExemplars, BrickBondNeedsEvenRowsAndLayers) {
  BrickParams params;
  params.rows_y = 3;
  EXPECT_THROW(brick_exemplar(16, 1, params), Error);
}

} // namespace
} // namespace texsim::vol
