#include "pipelines/turk_rd/pattern_sampler.hpp"

#include "core/error.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

namespace texsim::pipelines::turk_rd {
namespace {

using geom::Vec3;

std::vector<Vec3> random_cloud(std::size_t n, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> points(n);
  for (auto& p : points)
    p = Vec3(u(rng), u(rng), u(rng));
  return points;
}

std::vector<double> random_values(std::size_t n, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 5.0);
  std::vector<double> values(n);
  for (auto& v : values)
    v = u(rng);
  return values;
}

/// Scattered, unique ids (not 0..n-1, not in index order).
std::vector<std::int64_t> scattered_ids(std::size_t n, std::uint32_t seed) {
  std::vector<std::int64_t> ids(n);
  for (std::size_t i = 0; i < n; ++i)
    ids[i] = 1000 + 37 * std::int64_t(i);
  std::shuffle(ids.begin(), ids.end(), std::mt19937_64(seed));
  return ids;
}

/// Cells on a jittered square grid of spacing h over [0, 1]^2 (z = 0): evenly spread, as Turk's
/// relaxed cells are, but without the symmetry of an exact grid.
std::vector<Vec3> jittered_plane(double h, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.3 * h, 0.3 * h);
  const int n = int(std::lround(1.0 / h));
  std::vector<Vec3> cells;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      cells.emplace_back(i * h + u(rng), j * h + u(rng), 0.0);
  return cells;
}

/// Targets in the middle of the plane, away from its edges by more than the largest radius used.
std::vector<Vec3> plane_targets(std::size_t n, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.3, 0.7);
  std::vector<Vec3> targets(n);
  for (auto& p : targets)
    p = Vec3(u(rng), u(rng), 0.0);
  return targets;
}

double falloff(double d) {
  return d < 1.0 ? 2 * d * d * d - 3 * d * d + 1 : 0.0;
}

TEST(PatternSampler, FalloffIsTurksCubic) {
  EXPECT_EQ(turk_falloff(0.0), 1.0);
  EXPECT_DOUBLE_EQ(turk_falloff(0.5), 0.5);
  EXPECT_DOUBLE_EQ(turk_falloff(0.25), 2 * 0.015625 - 3 * 0.0625 + 1);
  EXPECT_EQ(turk_falloff(1.0), 0.0);
  EXPECT_EQ(turk_falloff(3.0), 0.0);
}

TEST(PatternSampler, ReproducesConstantsExactly) {
  const auto cells = random_cloud(2000, 1);
  const auto targets = random_cloud(500, 2);
  const PatternSampler sampler(targets, cells, scattered_ids(cells.size(), 3), 0.15);
  for (const double c : {1.0, -3.7, 1234.5678}) {
    const std::vector<double> values(cells.size(), c);
    const auto out = sampler.sample(values);
    ASSERT_EQ(out.size(), targets.size());
    for (std::size_t t = 0; t < out.size(); ++t)
      EXPECT_NEAR(out[t], c, 1e-14 * std::abs(c)) << "target " << t;
  }
}

TEST(PatternSampler, LinearFunctionErrorShrinksWithCellSpacing) {
  const auto targets = plane_targets(400, 7);
  const auto linear = [](const Vec3& p) { return 0.5 + 2.0 * p.x() - 1.5 * p.y(); };
  std::vector<double> rms_errors;
  for (const double h : {1.0 / 20, 1.0 / 40, 1.0 / 80, 1.0 / 160}) {
    const auto cells = jittered_plane(h, 11);
    std::vector<double> values(cells.size());
    std::transform(cells.begin(), cells.end(), values.begin(), linear);
    std::vector<std::int64_t> ids(cells.size());
    std::iota(ids.begin(), ids.end(), 0);
    const double radius = 2.5 * h; // a fixed number of cells per target, as the cells get denser
    const PatternSampler sampler(targets, cells, ids, radius);
    // pi R^2 / h^2 cells lie within the radius on average.
    EXPECT_NEAR(sampler.mean_cells_per_target(), M_PI * 2.5 * 2.5, 0.1 * M_PI * 2.5 * 2.5);
    EXPECT_EQ(sampler.nearest_cell_targets(), 0u);
    const auto out = sampler.sample(values);
    double sum = 0.0;
    for (std::size_t t = 0; t < targets.size(); ++t)
      sum += std::pow(out[t] - linear(targets[t]), 2);
    rms_errors.push_back(std::sqrt(sum / double(targets.size())));
  }
  for (std::size_t k = 0; k < rms_errors.size(); ++k) {
    RecordProperty("rms_error_" + std::to_string(k), std::to_string(rms_errors[k]));
    std::printf("h = 1/%d: rms error %.3e\n", 20 << k, rms_errors[k]);
  }
  for (std::size_t k = 1; k < rms_errors.size(); ++k) {
    // The weighted centroid of the cells around a target is off the target by O(h): halving the
    // spacing halves the error.
    const double ratio = rms_errors[k - 1] / rms_errors[k];
    EXPECT_GT(ratio, 1.6) << "refinement " << k;
    EXPECT_LT(ratio, 2.6) << "refinement " << k;
  }
  EXPECT_LT(rms_errors.back(), 2e-3);
}

TEST(PatternSampler, MatchesBruteForceFormulaOnRandomCloud) {
  const auto cells = random_cloud(1500, 21);
  const auto targets = random_cloud(300, 22);
  const auto values = random_values(cells.size(), 23);
  const auto ids = scattered_ids(cells.size(), 24);
  const double radius = 0.12;
  const PatternSampler sampler(targets, cells, ids, radius);
  const auto out = sampler.sample(values);
  for (std::size_t t = 0; t < targets.size(); ++t) {
    double weighted = 0.0, total = 0.0;
    std::size_t in_range = 0;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const double w = falloff((targets[t] - cells[c]).norm() / radius);
      weighted += w * values[c];
      total += w;
      in_range += w > 0.0;
    }
    ASSERT_GT(total, 0.0) << "target " << t << " has no cell in range: enlarge the radius";
    EXPECT_NEAR(out[t], weighted / total, 1e-13) << "target " << t;
    // The stored row is exactly the cells in range, in increasing id order, weights w / sum w.
    const auto row = sampler.row_cells(t);
    const auto weights = sampler.row_weights(t);
    ASSERT_EQ(row.size(), in_range) << "target " << t;
    for (std::size_t k = 0; k < row.size(); ++k) {
      if (k > 0) {
        EXPECT_LT(ids[row[k - 1]], ids[row[k]]);
      }
      EXPECT_NEAR(weights[k], falloff((targets[t] - cells[row[k]]).norm() / radius) / total, 1e-15);
    }
  }
}

TEST(PatternSampler, DependsOnlyOnDistances) {
  // A rigid motion of targets and cells together changes no distance, hence no value.
  const auto cells = random_cloud(1000, 31);
  const auto targets = random_cloud(200, 32);
  const auto values = random_values(cells.size(), 33);
  const auto ids = scattered_ids(cells.size(), 34);
  const Eigen::Affine3d motion = Eigen::Translation3d(3.0, -1.0, 7.5) *
                                 Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, -0.5).normalized());
  std::vector<Vec3> moved_cells(cells.size()), moved_targets(targets.size());
  std::transform(cells.begin(), cells.end(), moved_cells.begin(),
                 [&](const Vec3& p) { return Vec3(motion * p); });
  std::transform(targets.begin(), targets.end(), moved_targets.begin(),
                 [&](const Vec3& p) { return Vec3(motion * p); });
  const auto out = PatternSampler(targets, cells, ids, 0.15).sample(values);
  const auto moved = PatternSampler(moved_targets, moved_cells, ids, 0.15).sample(values);
  for (std::size_t t = 0; t < targets.size(); ++t)
    EXPECT_NEAR(out[t], moved[t], 1e-12) << "target " << t;
}

TEST(PatternSampler, FarTargetTakesNearestCellValue) {
  const auto cells = random_cloud(800, 41);
  const auto values = random_values(cells.size(), 42);
  const auto ids = scattered_ids(cells.size(), 43);
  const std::vector<Vec3> targets = {Vec3(0.5, 0.5, 0.5), Vec3(10.0, -3.0, 4.0),
                                     Vec3(-2.0, 0.4, 0.6)};
  const PatternSampler sampler(targets, cells, ids, 0.1);
  EXPECT_EQ(sampler.nearest_cell_targets(), 2u);
  const auto out = sampler.sample(values);
  for (std::size_t t = 1; t < targets.size(); ++t) {
    std::size_t nearest = 0;
    for (std::size_t c = 1; c < cells.size(); ++c)
      if ((targets[t] - cells[c]).squaredNorm() < (targets[t] - cells[nearest]).squaredNorm())
        nearest = c;
    EXPECT_EQ(out[t], values[nearest]) << "target " << t;
    ASSERT_EQ(sampler.row_cells(t).size(), 1u);
    EXPECT_EQ(sampler.row_weights(t)[0], 1.0);
  }
  EXPECT_NE(out[0], values[0]); // the first target is an average
}

TEST(PatternSampler, NearestCellTieGoesToSmallestId) {
  // Two cells at the same distance from a far target: the smaller id wins in either order.
  const std::vector<Vec3> targets = {Vec3(0.0, 0.0, 5.0)};
  const std::vector<Vec3> cells = {Vec3(1.0, 0.0, 0.0), Vec3(-1.0, 0.0, 0.0)};
  const std::vector<double> values = {10.0, 20.0};
  const std::vector<std::int64_t> ids = {8, 3};
  EXPECT_EQ(PatternSampler(targets, cells, ids, 0.5).sample(values)[0], 20.0);
  const std::vector<Vec3> swapped_cells = {cells[1], cells[0]};
  const std::vector<double> swapped_values = {20.0, 10.0};
  const std::vector<std::int64_t> swapped_ids = {3, 8};
  EXPECT_EQ(PatternSampler(targets, swapped_cells, swapped_ids, 0.5).sample(swapped_values)[0],
            20.0);
}

TEST(PatternSampler, IdenticalForPermutedCellsAndAnyThreadCount) {
  const auto cells = random_cloud(3000, 51);
  const auto targets = random_cloud(1000, 52);
  const auto values = random_values(cells.size(), 53);
  const auto ids = scattered_ids(cells.size(), 54);
  const double radius = 0.2;
  const auto reference = PatternSampler(targets, cells, ids, radius).sample(values);

  std::vector<std::size_t> order(cells.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937_64(55));
  std::vector<Vec3> permuted_cells(cells.size());
  std::vector<double> permuted_values(cells.size());
  std::vector<std::int64_t> permuted_ids(cells.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    permuted_cells[k] = cells[order[k]];
    permuted_values[k] = values[order[k]];
    permuted_ids[k] = ids[order[k]];
  }
  const int threads = omp_get_max_threads();
  for (const int n_threads : {1, 2, 3}) {
    omp_set_num_threads(n_threads);
    const auto permuted =
        PatternSampler(targets, permuted_cells, permuted_ids, radius).sample(permuted_values);
    for (std::size_t t = 0; t < targets.size(); ++t)
      ASSERT_EQ(permuted[t], reference[t]) << "target " << t << ", " << n_threads << " threads";
  }
  omp_set_num_threads(threads);
}

TEST(PatternSampler, RejectsInconsistentInput) {
  const auto cells = random_cloud(10, 61);
  const auto targets = random_cloud(5, 62);
  std::vector<std::int64_t> ids(cells.size());
  std::iota(ids.begin(), ids.end(), 0);
  EXPECT_THROW(PatternSampler(targets, cells, ids, 0.0), Error);
  EXPECT_THROW(PatternSampler(targets, cells, std::span(ids).first(9), 0.1), Error);
  EXPECT_THROW(PatternSampler(targets, {}, {}, 0.1), Error);
  auto repeated = ids;
  repeated[7] = repeated[2];
  EXPECT_THROW(PatternSampler(targets, cells, repeated, 0.1), Error);
  const PatternSampler sampler(targets, cells, ids, 0.1);
  std::vector<double> out(targets.size());
  EXPECT_THROW(sampler.sample(std::vector<double>(9, 1.0), out), Error);
  EXPECT_THROW(sampler.sample(std::vector<double>(10, 1.0), std::span(out).first(4)), Error);
  EXPECT_EQ(PatternSampler({}, {}, {}, 0.1).targets(), 0u);
}

} // namespace
} // namespace texsim::pipelines::turk_rd
