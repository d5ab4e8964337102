#include "par/morton_partition.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace texsim::par {
namespace {

TEST(MortonKey, InterleavesAxisBitsWithXLowest) {
  const std::array<double, 3> lo{0, 0, 0}, hi{1, 1, 1};
  EXPECT_EQ(morton_key({0, 0, 0}, lo, hi), 0u);
  const std::uint64_t top = (1u << 21) - 1;
  EXPECT_EQ(morton_key({1, 0, 0}, lo, hi), [&] {
    std::uint64_t key = 0;
    for (int bit = 0; bit < 21; ++bit)
      key |= ((top >> bit) & 1u) << (3 * bit);
    return key;
  }());
  EXPECT_EQ(morton_key({0, 1, 0}, lo, hi), morton_key({1, 0, 0}, lo, hi) << 1);
  EXPECT_EQ(morton_key({0, 0, 1}, lo, hi), morton_key({1, 0, 0}, lo, hi) << 2);
}

TEST(MortonPartition, PartsAreBalancedAndSpatiallyCompact) {
  // A 16^3 lattice cut into 8 parts: the Z-order curve gives exactly the eight octants.
  std::vector<std::array<double, 3>> points;
  for (int z = 0; z < 16; ++z)
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        points.push_back({double(x), double(y), double(z)});
  const auto part = morton_partition(points, 8);
  std::vector<int> count(8, 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ++count[part[i]];
    const int octant = (points[i][0] >= 8) + 2 * (points[i][1] >= 8) + 4 * (points[i][2] >= 8);
    EXPECT_EQ(part[i], octant) << "point " << i;
  }
  for (int c : count)
    EXPECT_EQ(c, 512);
}

TEST(MortonPartition, UnevenCountsDifferByAtMostOneAndIgnoreInputOrder) {
  std::vector<std::array<double, 3>> points;
  for (int i = 0; i < 1001; ++i)
    points.push_back({std::sin(i * 1.3), std::cos(i * 0.7), std::sin(i * 0.11)});
  const auto part = morton_partition(points, 3);
  std::vector<int> count(3, 0);
  for (int p : part)
    ++count[p];
  EXPECT_LE(*std::max_element(count.begin(), count.end()) -
                *std::min_element(count.begin(), count.end()),
            1);
  auto reversed = points;
  std::reverse(reversed.begin(), reversed.end());
  const auto part_reversed = morton_partition(reversed, 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_EQ(part[i], part_reversed[points.size() - 1 - i]);
}

} // namespace
} // namespace texsim::par
