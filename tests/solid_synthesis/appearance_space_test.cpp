#include "pipelines/solid_synthesis/appearance_space.hpp"

#include "core/rng.hpp"
#include "vol/gaussian_stack_3d.hpp"
#include "vol/procedural_exemplars.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Uniform random values in [0, 1).
vol::ChannelGrid random_grid(vol::Dims dims, int channels, std::uint64_t seed) {
  vol::ChannelGrid grid(dims, channels);
  const CounterRng rng(seed, 0);
  for (std::size_t v = 0; v < grid.data().size(); ++v) {
    grid.data()[v] = static_cast<float>(rng.uniform(v, 0));
  }
  return grid;
}

std::vector<double> grid_mean(const vol::ChannelGrid& grid) {
  std::vector<double> mean(static_cast<std::size_t>(grid.channels()), 0.0);
  for (std::size_t v = 0; v < grid.voxel_count(); ++v) {
    for (int c = 0; c < grid.channels(); ++c) {
      mean[static_cast<std::size_t>(c)] += grid.voxel(v)[static_cast<std::size_t>(c)];
    }
  }
  for (double& m : mean) {
    m /= static_cast<double>(grid.voxel_count());
  }
  return mean;
}

/// Bitwise equality of two float grids (NaN-safe, unlike ==).
bool same_bytes(const vol::ChannelGrid& a, const vol::ChannelGrid& b) {
  return a.dims() == b.dims() && a.channels() == b.channels() &&
         std::memcmp(a.data().data(), b.data().data(), a.data().size_bytes()) == 0;
}

TEST(GaussianStack3d, EachLevelIsTheDilatedBinomialConvolutionOfTheLast) {
  const vol::ChannelGrid grid = random_grid({8, 6, 5}, 2, 3);
  const double w[5] = {1.0 / 16, 4.0 / 16, 6.0 / 16, 4.0 / 16, 1.0 / 16};
  for (const bool periodic : {true, false}) {
    const auto stack = vol::gaussian_stack(grid, periodic);
    ASSERT_EQ(stack.size(), 4u);              // 2^3 >= 8
    const vol::ChannelGrid& level = stack[2]; // taps 2 apart on level 1, 1 apart on level 0
    const vol::ChannelGrid& finer = stack[1];
    for (int k = 0; k < 5; ++k) {
      for (int j = 0; j < 6; ++j) {
        for (int i = 0; i < 8; ++i) {
          for (int c = 0; c < 2; ++c) {
            double expected = 0.0;
            for (int tz = 0; tz < 5; ++tz) {
              for (int ty = 0; ty < 5; ++ty) {
                for (int tx = 0; tx < 5; ++tx) {
                  const int x = i + 2 * (tx - 2), y = j + 2 * (ty - 2), z = k + 2 * (tz - 2);
                  const std::size_t at =
                      periodic ? finer.periodic_index(x, y, z) : finer.clamped_index(x, y, z);
                  expected += w[tx] * w[ty] * w[tz] * finer.voxel(at)[static_cast<std::size_t>(c)];
                }
              }
            }
            EXPECT_NEAR(level.voxel(level.index(i, j, k))[static_cast<std::size_t>(c)], expected,
                        1e-6);
          }
        }
      }
    }
  }
}

TEST(GaussianStack3d, PeriodicStackKeepsTheMeanAndEndsConstant) {
  const vol::ChannelGrid grid = random_grid({16, 8, 4}, 3, 7);
  const auto stack = vol::gaussian_stack(grid, true);
  ASSERT_EQ(stack.size(), 5u);
  const std::vector<double> mean = grid_mean(grid);
  for (const vol::ChannelGrid& level : stack) {
    EXPECT_EQ(level.dims(), grid.dims());
    const std::vector<double> level_mean = grid_mean(level);
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_NEAR(level_mean[c], mean[c], 1e-6);
    }
  }
  for (std::size_t v = 0; v < grid.voxel_count(); ++v) {
    for (std::size_t c = 0; c < 3; ++c) {
      ASSERT_NEAR(stack.back().voxel(v)[c], mean[c], 1e-6);
    }
  }
}

TEST(GaussianStack3d, AnyRunOfPlanesIsTheSameBytesAsTheWholeBlur) {
  // Odd sizes and spacings up to past the grid, so taps wrap or clamp and repeat planes.
  const vol::ChannelGrid grid = random_grid({7, 5, 9}, 3, 11);
  const std::size_t plane = 7 * 5 * 3;
  for (const bool periodic : {true, false}) {
    for (const int spacing : {1, 2, 4, 16}) {
      const vol::ChannelGrid whole = vol::binomial_blur_3d(grid, spacing, periodic);
      for (const auto& [z_begin, z_end] :
           {std::pair{0, 9}, std::pair{0, 1}, std::pair{3, 5}, std::pair{8, 9}, std::pair{4, 4}}) {
        std::vector<float> planes(plane * static_cast<std::size_t>(z_end - z_begin));
        vol::binomial_blur_3d_planes(grid, spacing, periodic, z_begin, z_end, planes);
        const auto expected =
            whole.data().subspan(plane * static_cast<std::size_t>(z_begin), planes.size());
        EXPECT_EQ(std::memcmp(planes.data(), expected.data(), expected.size_bytes()), 0)
            << "periodic " << periodic << ", spacing " << spacing << ", planes [" << z_begin << ", "
            << z_end << ")";
      }
    }
  }
}

TEST(GaussianStack3d, ThreadCountDoesNotChangeTheStack) {
  const vol::ChannelGrid grid = random_grid({12, 12, 12}, 3, 1);
  omp_set_num_threads(1);
  const auto one = vol::gaussian_stack(grid, false);
  omp_set_num_threads(2);
  const auto two = vol::gaussian_stack(grid, false);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t s = 0; s < one.size(); ++s) {
    EXPECT_TRUE(same_bytes(one[s], two[s])) << s;
  }
}

/// The window^3 neighbourhood of (i, j, k) of `grid` with taps `spacing` apart, as doubles in the
/// appearance-space component order (taps z, y, x; channels fastest).
Eigen::VectorXd brute_neighbourhood(const vol::ChannelGrid& grid, int window, int spacing,
                                    bool periodic, int i, int j, int k) {
  const int r = window / 2, channels = grid.channels();
  Eigen::VectorXd out(window * window * window * channels);
  Eigen::Index p = 0;
  for (int dz = -r; dz <= r; ++dz) {
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        const int x = i + dx * spacing, y = j + dy * spacing, z = k + dz * spacing;
        const auto v =
            grid.voxel(periodic ? grid.periodic_index(x, y, z) : grid.clamped_index(x, y, z));
        for (int c = 0; c < channels; ++c) {
          out(p++) = v[static_cast<std::size_t>(c)];
        }
      }
    }
  }
  return out;
}

/// Brute-force neighbourhoods of every working voxel of level s: rows of the matrix, voxels x
/// fastest. `stack` is the uncropped stack, `cut` the voxels discarded per face.
Eigen::MatrixXd brute_neighbourhoods(const std::vector<vol::ChannelGrid>& stack, std::size_t s,
                                     int window, bool periodic, int cut) {
  const vol::ChannelGrid& level = stack[s];
  const vol::Dims d = level.dims();
  const int nx = d.nx - 2 * cut, ny = d.ny - 2 * cut, nz = d.nz - 2 * cut;
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(nx) * ny * nz,
                       window * window * window * level.channels());
  Eigen::Index m = 0;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        rows.row(m++) =
            brute_neighbourhood(level, window, 1 << s, periodic, i + cut, j + cut, k + cut);
      }
    }
  }
  return rows;
}

/// Features of a level as a voxels x dimensions matrix.
Eigen::MatrixXd feature_matrix(const vol::ChannelGrid& features) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(features.voxel_count()), features.channels());
  for (std::size_t v = 0; v < features.voxel_count(); ++v) {
    for (int q = 0; q < features.channels(); ++q) {
      out(static_cast<Eigen::Index>(v), q) = features.voxel(v)[static_cast<std::size_t>(q)];
    }
  }
  return out;
}

/// Mean, basis and features of every level against a brute-force PCA of explicitly gathered
/// neighbourhoods: the mean is the neighbourhoods' mean, the basis columns are orthonormal
/// eigenvectors of their covariance with the largest eigenvalues in order, and the features are
/// the centred neighbourhoods times the basis.
void expect_matches_brute_force_pca(const vol::ChannelGrid& exemplar, ExemplarBorder border) {
  AppearanceOptions options;
  options.border = border;
  const AppearanceSpace space = build_appearance_space(exemplar, options);
  const bool periodic = border == ExemplarBorder::toroidal;
  const int cut = periodic ? 0 : options.window / 2;
  const auto stack = vol::gaussian_stack(exemplar, periodic);
  ASSERT_EQ(space.levels.size(), stack.size());
  for (std::size_t s = 0; s + 1 < stack.size(); ++s) {
    const AppearanceLevel& level = space.levels[s];
    EXPECT_EQ(level.spacing, 1 << s);
    const Eigen::MatrixXd rows = brute_neighbourhoods(stack, s, options.window, periodic, cut);
    const Eigen::VectorXd mean = rows.colwise().mean();
    EXPECT_LT((level.mean - mean).cwiseAbs().maxCoeff(), 1e-6) << s;
    const Eigen::MatrixXd centred = rows.rowwise() - mean.transpose();
    const Eigen::MatrixXd covariance =
        centred.transpose() * centred / static_cast<double>(rows.rows());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
    const Eigen::Index d = level.basis.cols(), n = covariance.rows();
    ASSERT_EQ(d, options.dimensions);
    const Eigen::MatrixXd gram = level.basis.transpose() * level.basis;
    EXPECT_LT((gram - Eigen::MatrixXd::Identity(d, d)).cwiseAbs().maxCoeff(), 1e-9) << s;
    const Eigen::MatrixXd projected_covariance = level.basis.transpose() * covariance * level.basis;
    const double top = solver.eigenvalues()(n - 1);
    double kept = 0.0;
    for (Eigen::Index q = 0; q < d; ++q) {
      const double eigenvalue = solver.eigenvalues()(n - 1 - q);
      kept += eigenvalue;
      EXPECT_NEAR(projected_covariance(q, q), eigenvalue, 1e-5 * top) << s << " axis " << q;
      for (Eigen::Index r = 0; r < q; ++r) {
        EXPECT_NEAR(projected_covariance(q, r), 0.0, 1e-5 * top) << s;
      }
    }
    EXPECT_NEAR(level.retained_variance, kept / covariance.trace(), 1e-5) << s;
    const Eigen::MatrixXd features = feature_matrix(level.features);
    EXPECT_LT((features - centred * level.basis).cwiseAbs().maxCoeff(), 1e-5) << s;
  }
}

TEST(AppearanceSpace, ToroidalLevelsAreThePcaOfTheirNeighbourhoods) {
  expect_matches_brute_force_pca(vol::to_channels(vol::marble_exemplar(12, 2)),
                                 ExemplarBorder::toroidal);
}

TEST(AppearanceSpace, DiscardLevelsAreThePcaOfTheInteriorNeighbourhoods) {
  expect_matches_brute_force_pca(vol::to_channels(vol::particle_exemplar(14, 4)),
                                 ExemplarBorder::discard);
}

TEST(AppearanceSpace, FullDimensionKeepsAllVarianceAndPreservesDistances) {
  const vol::ChannelGrid exemplar = random_grid({6, 5, 4}, 3, 11);
  AppearanceOptions options;
  options.window = 3;
  options.dimensions = 3 * 3 * 3 * 3;
  const AppearanceSpace space = build_appearance_space(exemplar, options);
  const auto stack = vol::gaussian_stack(exemplar, true);
  for (std::size_t s = 0; s < 2; ++s) { // the finest levels: full rank
    const AppearanceLevel& level = space.levels[s];
    EXPECT_NEAR(level.retained_variance, 1.0, 1e-9) << s;
    const Eigen::MatrixXd rows = brute_neighbourhoods(stack, s, options.window, true, 0);
    const Eigen::MatrixXd features = feature_matrix(level.features);
    for (Eigen::Index a = 0; a < rows.rows(); ++a) {
      for (Eigen::Index b = a + 1; b < rows.rows(); b += 7) {
        const double raw = (rows.row(a) - rows.row(b)).norm();
        const double projected = (features.row(a) - features.row(b)).norm();
        ASSERT_NEAR(projected, raw, 1e-5 * (1.0 + raw)) << s << ": " << a << ", " << b;
      }
    }
  }
}

TEST(AppearanceSpace, CopiesInALatticeExemplarGetIdenticalFeatures) {
  const int n = 16, period = 4;
  const AppearanceSpace space =
      build_appearance_space(vol::to_channels(vol::lattice_exemplar(n, period, 5)), {});
  for (const AppearanceLevel& level : space.levels) {
    const vol::ChannelGrid& f = level.features;
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          const auto a = f.voxel(f.index(i, j, k));
          const auto b = f.voxel(f.index((i + period) % n, (j + 2 * period) % n, (k + period) % n));
          ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin()))
              << "spacing " << level.spacing << " voxel " << i << " " << j << " " << k;
        }
      }
    }
  }
}

TEST(AppearanceSpace, DiscardCropsEveryLevelByHalfAWindowPerFace) {
  const int n = 20;
  const vol::ChannelGrid exemplar = vol::to_channels(vol::wood_exemplar(n, 3));
  AppearanceOptions options;
  options.border = ExemplarBorder::discard;
  const AppearanceSpace space = build_appearance_space(exemplar, options);
  EXPECT_FALSE(space.periodic);
  const vol::Dims cropped{n - 4, n - 4, n - 4};
  EXPECT_EQ(space.colours.dims(), cropped);
  ASSERT_EQ(space.stack.size(), 6u); // 2^5 >= 20
  for (std::size_t s = 0; s < space.stack.size(); ++s) {
    EXPECT_EQ(space.stack[s].dims(), cropped);
    EXPECT_EQ(space.levels[s].features.dims(), cropped);
  }
  for (int k = 0; k < n - 4; ++k) {
    for (int j = 0; j < n - 4; ++j) {
      for (int i = 0; i < n - 4; ++i) {
        const auto a = space.colours.voxel(space.colours.index(i, j, k));
        const auto b = exemplar.voxel(exemplar.index(i + 2, j + 2, k + 2));
        ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin()));
      }
    }
  }
  EXPECT_TRUE(space.stack[0] == space.colours);
}

TEST(AppearanceSpace, BuildsAreBitwiseIdenticalForAnyThreadCount) {
  const vol::ChannelGrid exemplar = vol::to_channels(vol::noise_exemplar(16, 8));
  for (const ExemplarBorder border : {ExemplarBorder::toroidal, ExemplarBorder::discard}) {
    AppearanceOptions options;
    options.border = border;
    omp_set_num_threads(1);
    const AppearanceSpace one = build_appearance_space(exemplar, options);
    omp_set_num_threads(2);
    const AppearanceSpace two = build_appearance_space(exemplar, options);
    const AppearanceSpace again = build_appearance_space(exemplar, options);
    ASSERT_EQ(one.levels.size(), two.levels.size());
    for (std::size_t s = 0; s < one.levels.size(); ++s) {
      EXPECT_TRUE(same_bytes(one.levels[s].features, two.levels[s].features)) << s;
      EXPECT_TRUE(same_bytes(two.levels[s].features, again.levels[s].features)) << s;
      EXPECT_TRUE(one.levels[s].basis == two.levels[s].basis) << s;
      EXPECT_TRUE(one.levels[s].mean == two.levels[s].mean) << s;
      EXPECT_EQ(one.levels[s].retained_variance, two.levels[s].retained_variance) << s;
    }
  }
}

TEST(AppearanceSpace, BuildsSplitOverRanksAreBitwiseTheSerialOne) {
  // Levels' axes on different ranks, rows of every level projected by all: the same bits as one
  // process computing everything, on every rank. An odd exemplar size leaves uneven row shares.
  const vol::ChannelGrid exemplar = vol::to_channels(vol::noise_exemplar(15, 8));
  for (const ExemplarBorder border : {ExemplarBorder::toroidal, ExemplarBorder::discard}) {
    AppearanceOptions options;
    options.border = border;
    const AppearanceSpace serial = build_appearance_space(exemplar, options);
    const AppearanceSpace split = build_appearance_space(par::world(), exemplar, options);
    ASSERT_EQ(serial.levels.size(), split.levels.size());
    for (std::size_t s = 0; s < serial.levels.size(); ++s) {
      EXPECT_TRUE(same_bytes(serial.levels[s].features, split.levels[s].features))
          << "level " << s << " on rank " << par::world().rank << " of " << par::world().size;
      EXPECT_TRUE(serial.levels[s].basis == split.levels[s].basis) << s;
      EXPECT_TRUE(serial.levels[s].mean == split.levels[s].mean) << s;
      EXPECT_EQ(serial.levels[s].retained_variance, split.levels[s].retained_variance) << s;
    }
  }
}

TEST(AppearanceSpace, ConstantLevelsGiveZeroFeaturesWithoutNaN) {
  const AppearanceSpace flat =
      build_appearance_space(vol::ChannelGrid({8, 8, 8}, 3, 0.4f), AppearanceOptions{});
  for (const AppearanceLevel& level : flat.levels) {
    EXPECT_EQ(level.retained_variance, 1.0);
    EXPECT_TRUE(level.basis.isZero(0.0));
    for (const float f : level.features.data()) {
      ASSERT_EQ(f, 0.0f);
    }
  }
  // The coarsest level of a power-of-two periodic exemplar is its mean: no direction is kept.
  const AppearanceSpace marble =
      build_appearance_space(vol::to_channels(vol::marble_exemplar(16, 1)), AppearanceOptions{});
  const AppearanceLevel& coarsest = marble.levels.back();
  EXPECT_EQ(coarsest.spacing, 16);
  EXPECT_TRUE(coarsest.basis.isZero(0.0));
  for (const float f : coarsest.features.data()) {
    ASSERT_EQ(f, 0.0f);
  }
}

TEST(AppearanceSpace, ProjectNeighbourhoodReproducesTheFinestFeatures) {
  const int n = 12;
  const AppearanceSpace space =
      build_appearance_space(vol::to_channels(vol::brick_exemplar(n, 6)), AppearanceOptions{});
  const AppearanceLevel& finest = space.levels.front();
  std::vector<float> out(static_cast<std::size_t>(finest.basis.cols()));
  for (std::size_t v = 0; v < space.colours.voxel_count(); v += 5) {
    const int i = static_cast<int>(v % n), j = static_cast<int>(v / n % n),
              k = static_cast<int>(v / (n * n));
    project_neighbourhood(finest, space.colours, i, j, k, out);
    const auto expected = finest.features.voxel(v);
    for (std::size_t q = 0; q < out.size(); ++q) {
      ASSERT_NEAR(out[q], expected[q], 1e-5);
    }
  }
}

TEST(AppearanceSpace, ScalarExemplarsAndShortFeatureVectors) {
  const vol::ChannelGrid grey = random_grid({10, 10, 10}, 1, 4);
  AppearanceOptions options;
  options.window = 1;
  options.dimensions = 3; // more than the single component of a 1^3 grey neighbourhood
  const AppearanceSpace space = build_appearance_space(grey, options);
  const AppearanceLevel& finest = space.levels.front();
  EXPECT_EQ(finest.features.channels(), 3);
  EXPECT_NEAR(finest.retained_variance, 1.0, 1e-9);
  const double mean = grid_mean(grey)[0];
  for (std::size_t v = 0; v < grey.voxel_count(); ++v) {
    // One component: the feature is the centred value itself (the sign makes it positive).
    ASSERT_NEAR(finest.features.voxel(v)[0], grey.voxel(v)[0] - mean, 1e-6);
    ASSERT_EQ(finest.features.voxel(v)[1], 0.0f);
    ASSERT_EQ(finest.features.voxel(v)[2], 0.0f);
  }
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
