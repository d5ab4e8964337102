#include "img/image.hpp"

#include <gtest/gtest.h>

namespace texsim::img {
namespace {

GreyImage numbered(int width, int height) {
  GreyImage image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.at(x, y) = static_cast<float>(100 * y + x);
    }
  }
  return image;
}

TEST(Image, StorageIsRowMajorWithXFastest) {
  const GreyImage image = numbered(5, 3);
  ASSERT_EQ(image.size(), 15u);
  for (std::size_t i = 0; i < image.size(); ++i) {
    EXPECT_EQ(image.data()[i], static_cast<float>(100 * (i / 5) + i % 5));
  }
}

TEST(Image, PeriodicAccessWrapsNegativeAndLargeIndices) {
  const GreyImage image = numbered(5, 3);
  EXPECT_EQ(image.periodic(-1, 0), image.at(4, 0));
  EXPECT_EQ(image.periodic(5, 3), image.at(0, 0));
  EXPECT_EQ(image.periodic(-6, -4), image.at(4, 2));
  EXPECT_EQ(image.periodic(5 * 1000 + 2, -3 * 1000 + 1), image.at(2, 1));
  EXPECT_EQ(image.periodic(-5 * 1000 - 3, 3 * 777 + 2), image.at(2, 2));
}

TEST(Image, ClampedAccessExtendsTheBorder) {
  const GreyImage image = numbered(5, 3);
  EXPECT_EQ(image.clamped(-7, 1), image.at(0, 1));
  EXPECT_EQ(image.clamped(9, -2), image.at(4, 0));
  EXPECT_EQ(image.clamped(3, 50), image.at(3, 2));
}

TEST(Image, RejectsEmptySize) {
  EXPECT_THROW(RgbImage(0, 4), Error);
}

} // namespace
} // namespace texsim::img
