// The erosion test of Gagnon et al. 2021 (5.2) against hand values on a 4 x 4 exemplar: texel
// centres at 0.125, 0.375, 0.625, 0.875, so D = 1 - sqrt(2) / 4 on the four centre texels,
// 1 - sqrt(10) / 4 on the edge middles and 0 in the corners; the exemplar texel under uv wraps
// periodically; w = 1 keeps p, w = 0 erodes everything, and erosion never grows with w.
#include "pipelines/fluid_lapped/erosion_mask.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace texsim::pipelines::fluid_lapped {
namespace {

using Eigen::Vector2d;

const double kCentreD = 1.0 - std::sqrt(2.0) / 4.0; // |(0.375, 0.375) - (0.5, 0.5)| / 0.5
const double kEdgeD = 1.0 - std::sqrt(10.0) / 4.0;  // |(0.125, 0.375) - (0.5, 0.5)| / 0.5

TEST(ErosionMask, ExemplarTexelIsTheCellUnderUvRowZeroAtTheTopAndWraps) {
  const ErosionMask mask(std::vector<float>(16, 0.0f), 4, 4, 0.1);
  EXPECT_EQ(mask.exemplar_texel(Vector2d(0.1, 0.9)), (std::array<int, 2>{0, 0}));
  EXPECT_EQ(mask.exemplar_texel(Vector2d(0.1, 0.1)), (std::array<int, 2>{0, 3}));
  EXPECT_EQ(mask.exemplar_texel(Vector2d(0.6, 0.3)), (std::array<int, 2>{2, 2}));
  EXPECT_EQ(mask.exemplar_texel(Vector2d(1.0, 1.0)), (std::array<int, 2>{0, 3}));
  EXPECT_EQ(mask.exemplar_texel(Vector2d(-0.1, 0.1)), (std::array<int, 2>{3, 3}));
  EXPECT_EQ(mask.exemplar_texel(Vector2d(2.6, -0.7)), (std::array<int, 2>{2, 2}));
}

TEST(ErosionMask, FlatFeatureMapMatchesHandThresholds) {
  const double epsilon = 0.1;
  const ErosionMask mask(std::vector<float>(16, 0.0f), 4, 4, epsilon);
  EXPECT_NEAR(mask.normaliser(), std::sqrt(kCentreD), 1e-12);
  // Centre texel: shape 1, eroded iff 1 - epsilon < 1 - w, i.e. w < epsilon.
  EXPECT_FALSE(mask.eroded(Vector2d(0.5, 0.5), 1.0));
  EXPECT_FALSE(mask.eroded(Vector2d(0.4, 0.6), epsilon + 1e-6));
  EXPECT_TRUE(mask.eroded(Vector2d(0.4, 0.6), epsilon - 1e-6));
  // Edge texel (column 0, second row from the bottom): eroded iff w < 1 + epsilon - shape.
  const double shape = std::sqrt(kEdgeD) / std::sqrt(kCentreD);
  const double threshold = 1.0 + epsilon - shape;
  EXPECT_FALSE(mask.eroded(Vector2d(0.2, 0.3), threshold + 1e-6));
  EXPECT_TRUE(mask.eroded(Vector2d(0.2, 0.3), threshold - 1e-6));
  // Corner texel: shape 0, kept only for w > 1 + epsilon, which no weight reaches.
  EXPECT_TRUE(mask.eroded(Vector2d(0.05, 0.95), 1.0));
  // Outside [0, 1]^2 the texel repeats but D is taken at the unwrapped centre: 0.
  EXPECT_FALSE(mask.eroded(Vector2d(0.375, 0.375), 0.5));
  EXPECT_TRUE(mask.eroded(Vector2d(1.375, 0.375), 1.0));
}

TEST(ErosionMask, FeatureMapRaisesItsTexels) {
  // F = 1 in the top-left corner texel: the normaliser becomes 1 and that corner is kept like
  // p, while the centre texel now needs w > 1 + epsilon - sqrt(D).
  std::vector<float> feature(16, 0.0f);
  feature[0] = 1.0f;
  const double epsilon = 0.1;
  const ErosionMask mask(feature, 4, 4, epsilon);
  EXPECT_NEAR(mask.normaliser(), 1.0, 1e-12);
  EXPECT_FALSE(mask.eroded(Vector2d(0.05, 0.95), epsilon + 1e-6));
  EXPECT_TRUE(mask.eroded(Vector2d(0.05, 0.95), epsilon - 1e-6));
  EXPECT_TRUE(mask.eroded(Vector2d(0.95, 0.05), 1.0)); // the opposite corner has F = 0
  const double threshold = 1.0 + epsilon - std::sqrt(kCentreD);
  EXPECT_FALSE(mask.eroded(Vector2d(0.5, 0.5), threshold + 1e-6));
  EXPECT_TRUE(mask.eroded(Vector2d(0.5, 0.5), threshold - 1e-6));
}

TEST(ErosionMask, FullWeightKeepsTheCentreZeroWeightErodesAllAndErosionFallsWithWeight) {
  std::vector<float> feature(8 * 8);
  for (std::size_t i = 0; i < feature.size(); ++i)
    feature[i] = float((i * 37) % 11) / 10.0f;
  const ErosionMask mask(feature, 8, 8, 0.1);
  EXPECT_FALSE(mask.eroded(Vector2d(0.5, 0.5), 1.0));
  for (int i = 0; i < 400; ++i) {
    const Vector2d uv(-0.3 + 1.6 * ((i * 7) % 20) / 20.0, -0.3 + 1.6 * ((i * 13) % 20) / 20.0);
    EXPECT_TRUE(mask.eroded(uv, 0.0)) << uv.transpose();
    bool was_eroded = true;
    for (double w = 0.0; w <= 1.0; w += 0.05) {
      const bool eroded = mask.eroded(uv, w);
      EXPECT_TRUE(was_eroded || !eroded)
          << "eroded again at w = " << w << ", uv " << uv.transpose();
      was_eroded = eroded;
    }
  }
}

TEST(ErosionMask, TableLookupEqualsTheFormulaEvaluatedPerSample) {
  // The section 5.2 formula straight from its definition, on a 7 x 5 feature map, for uv inside
  // the unit square and in its repeats, against eroded()'s precomputed table.
  const int width = 7, height = 5;
  const double epsilon = 0.1;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0), spread(-2.0, 3.0);
  std::vector<float> feature(std::size_t(width * height));
  for (auto& f : feature)
    f = float(unit(random));
  const ErosionMask mask(feature, width, height, epsilon);
  const auto falloff = [](const Vector2d& c) {
    return std::max(0.0, 1.0 - (Vector2d(0.5, 0.5) - c).norm() / 0.5);
  };
  for (int trial = 0; trial < 20000; ++trial) {
    const Vector2d uv(spread(random), spread(random));
    const double w = unit(random);
    const auto texel = mask.exemplar_texel(uv);
    const double f = feature[std::size_t(texel[1] * width + texel[0])];
    const Vector2d centre((std::floor(uv.x() * width) + 0.5) / width,
                          (std::floor(uv.y() * height) + 0.5) / height);
    const bool expected = std::sqrt(f + falloff(centre)) / mask.normaliser() - epsilon < 1.0 - w;
    ASSERT_EQ(mask.eroded(uv, w), expected) << "uv " << uv.transpose() << ", w " << w;
  }
}

TEST(ErosionMask, RejectsAFeatureMapOfTheWrongSize) {
  EXPECT_ANY_THROW(ErosionMask(std::vector<float>(15, 0.0f), 4, 4, 0.1));
}

} // namespace
} // namespace texsim::pipelines::fluid_lapped
