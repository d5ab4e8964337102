#include "vol/procedural_exemplars.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace texsim::vol {
namespace {

using Generator = std::function<RgbGrid(int, std::uint64_t)>;

struct Case {
  const char* name;
  Generator make;
  bool seeded = true;     ///< different seeds give different exemplars
  bool tile_units = true; ///< a function of (i, j, k) / n: 2n^3 at even voxels is the n^3 one
  /// Axes along which the pattern has no deliberate breaks: seams must be no rougher there.
  bool continuous_axes[3] = {true, true, true};
};

const Case kCases[] = {
    {"marble", [](int n, std::uint64_t s) { return marble_exemplar(n, s); }},
    {"wood", [](int n, std::uint64_t s) { return wood_exemplar(n, s); }},
    {"particles", [](int n, std::uint64_t s) { return particle_exemplar(n, s); }},
    {"bricks", [](int n, std::uint64_t s) { return brick_exemplar(n, s); }},
    {"noise", [](int n, std::uint64_t s) { return noise_exemplar(n, s); }},
    // Strokes change abruptly between z-slabs, stripes only vary along y.
    {"strokes",
     [](int n, std::uint64_t s) { return stroke_exemplar(n, s); },
     true,
     true,
     {true, true, false}},
    {"stripes",
     [](int n, std::uint64_t) { return stripe_exemplar(n); },
     false,
     true,
     {false, true, false}},
    // Lattice cells are 8 voxels wide whatever n is.
    {"lattice", [](int n, std::uint64_t s) { return lattice_exemplar(n, 8, s); }, true, false},
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
    if (c.seeded) {
      EXPECT_NE(a, c.make(24, 6)) << c.name;
    }
    EXPECT_EQ(a.dims(), (Dims{24, 24, 24})) << c.name;
  }
}

TEST(ProceduralExemplars, SeamsAreNoRougherThanTheInterior) {
  for (const Case& c : kCases) {
    const RgbGrid grid = c.make(48, 3);
    for (int axis = 0; axis < 3; ++axis) {
      if (!c.continuous_axes[axis]) {
        continue;
      }
      const double interior = mean_step(grid, axis, false);
      const double seam = mean_step(grid, axis, true);
      EXPECT_GT(interior, 0.0) << c.name;
      EXPECT_LT(seam, 2.0 * interior + 1e-6) << c.name << " axis " << axis;
    }
  }
}

TEST(ProceduralExemplars, DoubleResolutionSampledAtEvenVoxelsIsTheSameTile) {
  for (const Case& c : kCases) {
    if (!c.tile_units) {
      continue;
    }
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

/// Luminance-like mean of the channels.
float brightness(const img::Rgb& v) {
  return (v.r + v.g + v.b) / 3.0f;
}

TEST(ProceduralExemplars, NoiseIsBlueGreenHomogeneousWithSparseHighlights) {
  const int n = 48;
  const RgbGrid grid = noise_exemplar(n, 4);
  // Homogeneous: the mean colour of each of the 8 octants is close to the global mean.
  img::Rgb octant_sum[8]{};
  img::Rgb total{};
  std::size_t highlights = 0;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const img::Rgb& v = grid.at(i, j, k);
        octant_sum[(i * 2 / n) + 2 * (j * 2 / n) + 4 * (k * 2 / n)] += v;
        total += v;
        highlights += brightness(v) > 0.75f ? 1 : 0;
      }
    }
  }
  const img::Rgb mean = total * (1.0f / static_cast<float>(grid.size()));
  EXPECT_GT(mean.g, mean.r + 0.1f);
  EXPECT_GT(mean.b, mean.r + 0.1f);
  for (const img::Rgb& octant : octant_sum) {
    EXPECT_LT(colour_distance(octant * (8.0f / static_cast<float>(grid.size())), mean), 0.1);
  }
  const double highlight_fraction =
      static_cast<double>(highlights) / static_cast<double>(grid.size());
  EXPECT_GT(highlight_fraction, 0.002);
  EXPECT_LT(highlight_fraction, 0.08);
}

/// Correlation coefficient of the brightness of voxels v and v + offset, over the voxels v whose
/// z coordinate satisfies `use_z`.
template <class UseZ>
double brightness_correlation(const RgbGrid& grid, const int offset[3], const UseZ& use_z) {
  const int n = grid.dims().nx;
  double sa = 0.0, sb = 0.0, saa = 0.0, sbb = 0.0, sab = 0.0;
  std::size_t count = 0;
  for (int k = 0; k < n; ++k) {
    if (!use_z(k)) {
      continue;
    }
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const double a = brightness(grid.at(i, j, k));
        const double b = brightness(grid.periodic(i + offset[0], j + offset[1], k + offset[2]));
        sa += a;
        sb += b;
        saa += a * a;
        sbb += b * b;
        sab += a * b;
        ++count;
      }
    }
  }
  const double m = static_cast<double>(count);
  const double cov = sab / m - sa / m * sb / m;
  return cov / std::sqrt((saa / m - sa / m * sa / m) * (sbb / m - sb / m * sb / m));
}

TEST(ProceduralExemplars, StrokesAreContinuousInXYAndBrokenBetweenZSlabs) {
  const int n = 64;
  StrokeParams params;
  const int slab = n / params.layers;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const RgbGrid grid = stroke_exemplar(n, seed, params);
    // Constant along z inside a slab.
    for (int k = 0; k < n; ++k) {
      if ((k + 1) % slab != 0) {
        for (int j = 0; j < n; ++j) {
          for (int i = 0; i < n; ++i) {
            ASSERT_EQ(grid.at(i, j, k), grid.at(i, j, k + 1));
          }
        }
      }
    }
    // Neighbours along x and y are strongly related; the last voxel of a slab and the first of
    // the next are not.
    const int along_x[3] = {1, 0, 0}, along_y[3] = {0, 1, 0}, along_z[3] = {0, 0, 1};
    const auto everywhere = [](int) { return true; };
    const auto slab_ends = [&](int k) { return (k + 1) % slab == 0; };
    EXPECT_GT(brightness_correlation(grid, along_x, everywhere), 0.3) << seed;
    EXPECT_GT(brightness_correlation(grid, along_y, everywhere), 0.3) << seed;
    EXPECT_LT(std::abs(brightness_correlation(grid, along_z, slab_ends)), 0.2) << seed;
    // Both black and white strokes are drawn.
    float darkest = 1.0f, brightest = 0.0f;
    for (const img::Rgb& v : grid.data()) {
      darkest = std::min(darkest, brightness(v));
      brightest = std::max(brightest, brightness(v));
    }
    EXPECT_LT(darkest, 0.1f);
    EXPECT_GT(brightest, 0.9f);
  }
}

TEST(ProceduralExemplars, StripesFollowTheCosineProfileOfY) {
  const int n = 32;
  StripeParams params;
  const RgbGrid grid = stripe_exemplar(n, params);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      const double t = 0.5 + 0.5 * std::cos(2.0 * M_PI * params.periods * j / n);
      const img::Rgb expected = img::lerp(params.dark, params.light, static_cast<float>(t));
      for (int i = 0; i < n; ++i) {
        ASSERT_LT(colour_distance(grid.at(i, j, k), expected), 1e-5) << i << " " << j << " " << k;
      }
    }
  }
}

TEST(ProceduralExemplars, LatticeRepeatsExactlyEveryPeriod) {
  const int n = 24, period = 6;
  const RgbGrid grid = lattice_exemplar(n, period, 3);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const img::Rgb& v = grid.at(i, j, k);
        ASSERT_EQ(v, grid.periodic(i + period, j, k));
        ASSERT_EQ(v, grid.periodic(i, j + period, k));
        ASSERT_EQ(v, grid.periodic(i, j, k + period));
      }
    }
  }
  // Not constant inside a cell: every voxel of the cell differs from its x neighbour.
  std::size_t equal_neighbours = 0;
  for (int i = 0; i < period; ++i) {
    equal_neighbours += grid.at(i, 0, 0) == grid.at(i + 1, 0, 0) ? 1 : 0;
  }
  EXPECT_EQ(equal_neighbours, 0u);
  EXPECT_THROW(lattice_exemplar(20, 6, 3), Error);
}

} // namespace
} // namespace texsim::vol
