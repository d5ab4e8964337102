// UncoveredTexelIndex against a brute-force scan: every texel inside a box is visited once and no
// other, for boxes inside, across and outside the texels' extent, including empty and negative
// ones (sampling boxes reach past the atlas border).
#include "pipelines/fluid_lapped/uncovered_texel_index.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace texsim::pipelines::fluid_lapped {
namespace {

TEST(UncoveredTexelIndex, VisitsExactlyTheTexelsInsideTheBox) {
  std::mt19937 random(5);
  std::uniform_int_distribution<int> coordinate(0, 300);
  std::vector<UncoveredTexel> texels;
  const auto add = [&](int x, int y) {
    UncoveredTexel texel;
    texel.x = x;
    texel.y = y;
    texels.push_back(texel);
  };
  for (int i = 0; i < 2000; ++i)
    add(coordinate(random), coordinate(random));
  // A dense run of one row, as the first uncovered texels of an atlas often are.
  for (int x = 40; x < 140; ++x)
    add(x, 17);
  const UncoveredTexelIndex index(texels);
  std::uniform_int_distribution<int> corner(-40, 340), extent(0, 90);
  for (int trial = 0; trial < 500; ++trial) {
    const int x0 = corner(random), y0 = corner(random);
    const geom::TexelRect box{x0, y0, x0 + extent(random), y0 + extent(random)};
    std::vector<std::int32_t> visited, expected;
    index.for_each_inside(box, [&](std::int32_t i) { visited.push_back(i); });
    for (std::size_t i = 0; i < texels.size(); ++i)
      if (texels[i].x >= box.x0 && texels[i].x < box.x1 && texels[i].y >= box.y0 &&
          texels[i].y < box.y1)
        expected.push_back(std::int32_t(i));
    std::sort(visited.begin(), visited.end());
    ASSERT_EQ(visited, expected) << "box " << box.x0 << " " << box.y0 << " " << box.x1 << " "
                                 << box.y1;
  }
  const UncoveredTexelIndex empty(std::span<const UncoveredTexel>{});
  int calls = 0;
  empty.for_each_inside({0, 0, 100, 100}, [&](std::int32_t) { ++calls; });
  EXPECT_EQ(calls, 0);
}

} // namespace
} // namespace texsim::pipelines::fluid_lapped
