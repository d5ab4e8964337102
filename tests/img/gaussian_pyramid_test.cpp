#include "img/gaussian_pyramid.hpp"

#include "core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace texsim::img {
namespace {

GreyImage random_grey(int width, int height, std::uint64_t seed) {
  const CounterRng rng(seed, 2);
  GreyImage image(width, height);
  for (std::size_t i = 0; i < image.size(); ++i) {
    image.data()[i] = static_cast<float>(rng.uniform(i, 0));
  }
  return image;
}

double mean(const GreyImage& image) {
  double sum = 0.0;
  for (float v : image.data()) {
    sum += v;
  }
  return sum / static_cast<double>(image.size());
}

TEST(GaussianPyramid, ConstantImageStaysConstant) {
  for (Border border : {Border::periodic, Border::clamped}) {
    const RgbImage image(32, 16, Rgb{0.25f, 0.5f, 0.75f});
    for (const RgbImage& level : gaussian_pyramid(image, 4, border)) {
      for (const Rgb& p : level.data()) {
        EXPECT_NEAR(p.r, 0.25f, 1e-6f);
        EXPECT_NEAR(p.g, 0.5f, 1e-6f);
        EXPECT_NEAR(p.b, 0.75f, 1e-6f);
      }
    }
  }
}

TEST(GaussianPyramid, LevelSizesHalve) {
  const auto periodic = gaussian_pyramid(random_grey(64, 32, 1), 5, Border::periodic);
  ASSERT_EQ(periodic.size(), 5u);
  for (std::size_t l = 0; l < periodic.size(); ++l) {
    EXPECT_EQ(periodic[l].width(), 64 >> l);
    EXPECT_EQ(periodic[l].height(), 32 >> l);
  }
  const auto clamped = gaussian_pyramid(random_grey(13, 5, 1), 4, Border::clamped);
  EXPECT_EQ(clamped[1].width(), 7);
  EXPECT_EQ(clamped[1].height(), 3);
  EXPECT_EQ(clamped[3].width(), 2);
  EXPECT_EQ(clamped[3].height(), 1);
  EXPECT_THROW(gaussian_pyramid(random_grey(6, 6, 1), 3, Border::periodic), Error); // 3 is odd
}

TEST(GaussianPyramid, PeriodicPyramidPreservesTheMeanAtEveryLevel) {
  const auto pyramid = gaussian_pyramid(random_grey(64, 64, 7), 6, Border::periodic);
  const double mean0 = mean(pyramid[0]);
  for (const GreyImage& level : pyramid) {
    EXPECT_NEAR(mean(level), mean0, 1e-6);
  }
}

TEST(GaussianPyramid, CheckerboardOfPeriodTwoVanishesAtLevelOne) {
  GreyImage checker(16, 16);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      checker.at(x, y) = (x + y) % 2 == 0 ? 1.0f : 0.0f;
    }
  }
  const auto pyramid = gaussian_pyramid(checker, 2, Border::periodic);
  for (float v : pyramid[1].data()) {
    EXPECT_NEAR(v, 0.5f, 1e-6f);
  }
}

TEST(GaussianStack, SubsampledStackLevelsEqualPyramidLevels) {
  const GreyImage image = random_grey(32, 32, 5);
  const auto pyramid = gaussian_pyramid(image, 4, Border::periodic);
  const auto stack = gaussian_stack(image, 4, Border::periodic);
  ASSERT_EQ(stack.size(), 4u);
  for (int l = 0; l < 4; ++l) {
    const int step = 1 << l;
    EXPECT_EQ(stack[static_cast<std::size_t>(l)].width(), 32);
    for (int y = 0; y < pyramid[static_cast<std::size_t>(l)].height(); ++y) {
      for (int x = 0; x < pyramid[static_cast<std::size_t>(l)].width(); ++x) {
        EXPECT_NEAR(stack[static_cast<std::size_t>(l)].at(x * step, y * step),
                    pyramid[static_cast<std::size_t>(l)].at(x, y), 1e-6f);
      }
    }
  }
}

TEST(GaussianStack, ClampedStackLevelsGetSmoother) {
  const auto stack = gaussian_stack(random_grey(40, 24, 9), 3, Border::clamped);
  auto roughness = [](const GreyImage& im) {
    double sum = 0.0;
    for (int y = 0; y < im.height(); ++y) {
      for (int x = 0; x + 1 < im.width(); ++x) {
        sum += std::abs(im.at(x + 1, y) - im.at(x, y));
      }
    }
    return sum;
  };
  EXPECT_LT(roughness(stack[1]), 0.5 * roughness(stack[0]));
  EXPECT_LT(roughness(stack[2]), roughness(stack[1]));
}

} // namespace
} // namespace texsim::img
