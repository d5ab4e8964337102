#include "pipelines/solid_synthesis/synthesis_metrics.hpp"

#include "core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr int kNeighbourhood = 125; // 5^3

/// A grid of uniform random values in [0, 1).
vol::ChannelGrid random_grid(int n, int channels, std::uint64_t seed) {
  vol::ChannelGrid grid({n, n, n}, channels);
  const CounterRng rng(seed, 0);
  for (std::size_t v = 0; v < grid.data().size(); ++v) {
    grid.data()[v] = static_cast<float>(rng.uniform(v, 0));
  }
  return grid;
}

/// The raw 5^3 values of a 1-channel grid around (i, j, k), periodic.
void raw_neighbourhood(const vol::ChannelGrid& grid, int i, int j, int k, std::span<float> out) {
  int m = 0;
  for (int dz = -2; dz <= 2; ++dz) {
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) {
        out[m++] = grid.voxel(grid.periodic_index(i + dx, j + dy, k + dz))[0];
      }
    }
  }
}

/// A fixed random linear map from the raw neighbourhood to `dimension` features.
NeighbourhoodProjection random_projection(int dimension) {
  std::vector<float> weights(static_cast<std::size_t>(dimension) * kNeighbourhood);
  const CounterRng rng(11, 1);
  for (std::size_t w = 0; w < weights.size(); ++w) {
    weights[w] = static_cast<float>(rng.normal(w, 0));
  }
  return [weights, dimension](const vol::ChannelGrid& grid, int i, int j, int k,
                              std::span<float> out) {
    float raw[kNeighbourhood];
    raw_neighbourhood(grid, i, j, k, raw);
    for (int d = 0; d < dimension; ++d) {
      float sum = 0.0f;
      for (int m = 0; m < kNeighbourhood; ++m) {
        sum += weights[static_cast<std::size_t>(d) * kNeighbourhood + m] * raw[m];
      }
      out[d] = sum;
    }
  };
}

/// Every voxel's appearance vector under `project`.
vol::ChannelGrid features(const vol::ChannelGrid& grid, const NeighbourhoodProjection& project,
                          int dimension) {
  vol::ChannelGrid out(grid.dims(), dimension);
  const vol::Dims d = grid.dims();
  for (int k = 0; k < d.nz; ++k) {
    for (int j = 0; j < d.ny; ++j) {
      for (int i = 0; i < d.nx; ++i) {
        project(grid, i, j, k, out.voxel(out.index(i, j, k)));
      }
    }
  }
  return out;
}

/// neighbourhood_error by brute force, in double.
double brute_force_error(const vol::ChannelGrid& result, const vol::ChannelGrid& exemplar_features,
                         const NeighbourhoodProjection& project, int stride) {
  const int dimension = exemplar_features.channels();
  const std::size_t count = exemplar_features.voxel_count();
  std::vector<double> mean(dimension, 0.0);
  for (std::size_t v = 0; v < count; ++v) {
    for (int c = 0; c < dimension; ++c) {
      mean[c] += exemplar_features.voxel(v)[c] / static_cast<double>(count);
    }
  }
  double spread = 0.0;
  for (std::size_t v = 0; v < count; ++v) {
    double squared = 0.0;
    for (int c = 0; c < dimension; ++c) {
      squared += std::pow(exemplar_features.voxel(v)[c] - mean[c], 2);
    }
    spread += std::sqrt(squared) / static_cast<double>(count);
  }
  std::vector<float> query(dimension);
  double sum = 0.0;
  int samples = 0;
  const vol::Dims d = result.dims();
  for (int k = 0; k < d.nz; k += stride) {
    for (int j = 0; j < d.ny; j += stride) {
      for (int i = 0; i < d.nx; i += stride) {
        project(result, i, j, k, query);
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t v = 0; v < count; ++v) {
          double squared = 0.0;
          for (int c = 0; c < dimension; ++c) {
            squared += std::pow(static_cast<double>(query[c]) - exemplar_features.voxel(v)[c], 2);
          }
          best = std::min(best, squared);
        }
        sum += std::sqrt(best);
        ++samples;
      }
    }
  }
  return sum / samples / spread;
}

/// A 2n^3 tiling of the n^3 periodic `exemplar`, shifted by (3, 5, 1).
vol::ChannelGrid shifted_tiling(const vol::ChannelGrid& exemplar) {
  const int n = exemplar.dims().nx;
  vol::ChannelGrid result({2 * n, 2 * n, 2 * n}, 1);
  for (int k = 0; k < 2 * n; ++k) {
    for (int j = 0; j < 2 * n; ++j) {
      for (int i = 0; i < 2 * n; ++i) {
        result.voxel(result.index(i, j, k))[0] =
            exemplar.voxel(exemplar.periodic_index(i + 3, j + 5, k + 1))[0];
      }
    }
  }
  return result;
}

TEST(SynthesisMetrics, NeighbourhoodErrorIsZeroForAShiftedCopyOfThePeriodicExemplar) {
  const vol::ChannelGrid exemplar = random_grid(8, 1, 1);
  const vol::ChannelGrid result = shifted_tiling(exemplar);
  const vol::ChannelGrid raw_features = features(exemplar, raw_neighbourhood, kNeighbourhood);
  EXPECT_EQ(neighbourhood_error(result, raw_features, raw_neighbourhood, 1), 0.0);
  const NeighbourhoodProjection projection = random_projection(8);
  EXPECT_EQ(neighbourhood_error(result, features(exemplar, projection, 8), projection, 3), 0.0);
}

TEST(SynthesisMetrics, NeighbourhoodErrorOfNoiseMatchesBruteForce) {
  const vol::ChannelGrid exemplar = random_grid(8, 1, 1);
  const vol::ChannelGrid noise = random_grid(16, 1, 2);
  for (const int dimension : {8, kNeighbourhood}) {
    const NeighbourhoodProjection projection = dimension == kNeighbourhood
                                                   ? NeighbourhoodProjection(raw_neighbourhood)
                                                   : random_projection(dimension);
    const vol::ChannelGrid exemplar_features = features(exemplar, projection, dimension);
    const double error = neighbourhood_error(noise, exemplar_features, projection, 2);
    EXPECT_GT(error, 0.1) << dimension;
    EXPECT_NEAR(error, brute_force_error(noise, exemplar_features, projection, 2), 1e-5 * error)
        << dimension;
  }
}

// The tree's nearest distances against a full scan with the same metric, to the bit, on
// features of three kinds: uniform noise, smooth (few distinct directions, long runs of close
// values) and tie-heavy (values from 3 levels, so most queries have many equally near voxels and
// many an exact match); queries half exemplar rows, half perturbed.
TEST(SynthesisMetrics, NearestDistancesAreAFullScansBits) {
  const CounterRng rng(21, 0);
  for (const int channels : {3, 8, 40}) {
    for (const int kind : {0, 1, 2}) {
      vol::ChannelGrid exemplar({12, 10, 9}, channels);
      for (std::size_t v = 0; v < exemplar.voxel_count(); ++v)
        for (int c = 0; c < channels; ++c) {
          const double u = rng.uniform(v * 64 + std::size_t(c), std::uint64_t(kind));
          exemplar.voxel(v)[c] = kind == 0   ? float(u)
                                 : kind == 1 ? float(std::sin(0.05 * double(v) * (c + 1)))
                                             : float(std::floor(3 * u));
        }
      std::vector<float> queries;
      for (std::size_t q = 0; q < 400; ++q)
        for (int c = 0; c < channels; ++c) {
          const float base = exemplar.voxel((q * 7) % exemplar.voxel_count())[c];
          queries.push_back(q % 2 == 0 ? base : base + float(0.3 * rng.normal(q * 64 + c, 9)));
        }
      const std::vector<double> fast = nearest_appearance_distances(queries, exemplar);
      ASSERT_EQ(fast.size(), 400u);
      for (std::size_t q = 0; q < fast.size(); ++q) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t v = 0; v < exemplar.voxel_count(); ++v) {
          double squared = 0.0;
          for (int c = 0; c < channels; ++c) {
            const double d = double(queries[q * channels + c]) - double(exemplar.voxel(v)[c]);
            squared += d * d;
          }
          best = std::min(best, squared);
        }
        ASSERT_EQ(fast[q], std::sqrt(best))
            << channels << " channels, kind " << kind << ", query " << q;
        if (q % 2 == 0) {
          EXPECT_EQ(fast[q], 0.0); // an exemplar row is its own nearest
        }
      }
    }
  }
}

TEST(SynthesisMetrics, NeighbourhoodErrorDoesNotDependOnTheFeatureScale) {
  const vol::ChannelGrid exemplar = random_grid(8, 1, 3);
  const vol::ChannelGrid noise = random_grid(8, 1, 4);
  const NeighbourhoodProjection projection = random_projection(6);
  const NeighbourhoodProjection scaled = [&](const vol::ChannelGrid& grid, int i, int j, int k,
                                             std::span<float> out) {
    projection(grid, i, j, k, out);
    for (float& value : out) {
      value *= 4.0f; // a power of two: exact in float
    }
  };
  EXPECT_NEAR(neighbourhood_error(noise, features(exemplar, projection, 6), projection, 2),
              neighbourhood_error(noise, features(exemplar, scaled, 6), scaled, 2), 1e-9);
}

TEST(SynthesisMetrics, HistogramDistance) {
  const vol::ChannelGrid colours = random_grid(6, 3, 5);
  EXPECT_EQ(histogram_distance(colours, colours), 0.0);
  EXPECT_EQ(histogram_distance(vol::ChannelGrid({4, 4, 4}, 3, 0.1f),
                               vol::ChannelGrid({2, 3, 5}, 3, 0.9f)),
            1.0);
  // Values beyond [0, 1] are clamped into the end bins.
  EXPECT_EQ(histogram_distance(vol::ChannelGrid({2, 2, 2}, 1, 1.5f),
                               vol::ChannelGrid({2, 2, 2}, 1, 0.95f)),
            0.0);
  // Half of the voxels moved to another bin in one channel only: the joint histogram sees it.
  vol::ChannelGrid half = colours;
  vol::ChannelGrid all = colours;
  for (std::size_t v = 0; v < colours.voxel_count(); ++v) {
    half.voxel(v)[0] = 0.05f;
    half.voxel(v)[1] = 0.05f;
    half.voxel(v)[2] = v % 2 == 0 ? 0.05f : 0.55f;
    all.voxel(v)[0] = all.voxel(v)[1] = all.voxel(v)[2] = 0.05f;
  }
  EXPECT_DOUBLE_EQ(histogram_distance(half, all), 0.5);
  // Between two noise grids: small but not zero (sampling noise over 8^3 bins).
  const double noise = histogram_distance(random_grid(32, 3, 6), random_grid(32, 3, 7));
  EXPECT_GT(noise, 0.0);
  EXPECT_LT(noise, 0.15);
}

/// Colour stripes cos(2 pi (a i + b j) / n) on an n x n x 2 grid: periodic, constant along
/// (-b, a).
vol::ChannelGrid stripes(int n, int a, int b) {
  vol::ChannelGrid grid({n, n, 2}, 3);
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const float wave =
            static_cast<float>(std::cos(2.0 * std::numbers::pi * (a * i + b * j) / n));
        auto c = grid.voxel(grid.index(i, j, k));
        c[0] = 0.5f + 0.4f * wave;
        c[1] = 0.5f - 0.3f * wave;
        c[2] = 0.2f;
      }
    }
  }
  return grid;
}

TEST(SynthesisMetrics, StripeOrientationIsRecovered) {
  struct Case {
    int a, b;
    double degrees;
  };
  // Integer wave vectors (so the stripes tile) whose stripes run at about the named angle.
  for (const Case& c : {Case{0, 8, 0.0}, Case{-4, 7, 30.0}, Case{5, 5, -45.0}, Case{8, 0, 90.0},
                        Case{7, -4, 60.0}}) {
    EXPECT_NEAR(xy_stripe_orientation_degrees(stripes(128, c.a, c.b)), c.degrees, 1.0)
        << c.a << ", " << c.b;
  }
  // 1-channel input and a pattern that also varies along z.
  vol::ChannelGrid grey({64, 64, 8}, 1);
  for (int k = 0; k < 8; ++k) {
    for (int j = 0; j < 64; ++j) {
      for (int i = 0; i < 64; ++i) {
        grey.voxel(grey.index(i, j, k))[0] =
            static_cast<float>(std::sin(2.0 * std::numbers::pi * (3 * i + 3 * j + 2 * k) / 64.0));
      }
    }
  }
  EXPECT_NEAR(xy_stripe_orientation_degrees(grey), -45.0, 1e-6);
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
