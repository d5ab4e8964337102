#include "vol/dense_grid.hpp"

#include <gtest/gtest.h>

namespace texsim::vol {
namespace {

ScalarGrid numbered(Dims d) {
  ScalarGrid grid(d);
  for (int k = 0; k < d.nz; ++k) {
    for (int j = 0; j < d.ny; ++j) {
      for (int i = 0; i < d.nx; ++i) {
        grid.at(i, j, k) = static_cast<float>(10000 * k + 100 * j + i);
      }
    }
  }
  return grid;
}

TEST(DenseGrid, StorageIsXFastest) {
  const ScalarGrid grid = numbered({5, 7, 3});
  ASSERT_EQ(grid.size(), 105u);
  for (std::size_t n = 0; n < grid.size(); ++n) {
    const std::size_t i = n % 5, j = (n / 5) % 7, k = n / 35;
    EXPECT_EQ(grid.data()[n], static_cast<float>(10000 * k + 100 * j + i));
  }
}

TEST(DenseGrid, PeriodicAccessWrapsNegativeAndLargeIndicesExactly) {
  const ScalarGrid grid = numbered({5, 7, 3});
  for (int k = -7; k < 10; ++k) {
    for (int j = -15; j < 16; ++j) {
      for (int i = -11; i < 12; ++i) {
        const int wi = ((i % 5) + 5) % 5, wj = ((j % 7) + 7) % 7, wk = ((k % 3) + 3) % 3;
        ASSERT_EQ(grid.periodic(i, j, k), grid.at(wi, wj, wk)) << i << " " << j << " " << k;
      }
    }
  }
  EXPECT_EQ(grid.periodic(5 * 100000 + 4, -7 * 100000 + 6, 3 * 100000 + 2), grid.at(4, 6, 2));
  EXPECT_EQ(grid.periodic(-5 * 100000 - 1, -7 * 100000 - 7, -3 * 100000 - 3), grid.at(4, 0, 0));
}

TEST(DenseGrid, ClampedAccessExtendsTheBoundary) {
  const ScalarGrid grid = numbered({5, 7, 3});
  EXPECT_EQ(grid.clamped(-4, 3, 1), grid.at(0, 3, 1));
  EXPECT_EQ(grid.clamped(9, 70, -1), grid.at(4, 6, 0));
  EXPECT_EQ(grid.clamped(2, -1, 3), grid.at(2, 0, 2));
}

TEST(DenseGrid, EqualityComparesGeometryAndValues) {
  ScalarGrid a = numbered({2, 2, 2});
  ScalarGrid b = a;
  EXPECT_EQ(a, b);
  b.set_spacing({1.0, 2.0, 1.0});
  EXPECT_NE(a, b);
  b = a;
  b.at(1, 1, 1) += 1.0f;
  EXPECT_NE(a, b);
  EXPECT_THROW(RgbGrid(Dims{0, 1, 1}), Error);
}

} // namespace
} // namespace texsim::vol
