#include "img/colour_histogram.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <span>
#include <vector>

namespace texsim::img {
namespace {

std::vector<float> random_values(std::size_t count, std::uint64_t seed) {
  const CounterRng rng(seed, 0);
  std::vector<float> values(count);
  for (std::size_t v = 0; v < count; ++v)
    values[v] = static_cast<float>(rng.uniform(-0.2, 1.2, v, 0)); // some clamped at each end
  return values;
}

TEST(ColourHistogram, PartsAddUpToTheWholeExactly) {
  // Counting a set in parts (each rank its slab) gives the counts, and the distance, of counting
  // it at once.
  const std::vector<float> a = random_values(3 * 1000, 1), b = random_values(3 * 700, 2);
  ColourHistogram whole(3), first(3), second(3), other(3);
  whole.add(a);
  first.add(std::span<const float>(a).first(3 * 400));
  second.add(std::span<const float>(a).subspan(3 * 400));
  other.add(b);
  for (std::size_t bin = 0; bin < whole.counts().size(); ++bin)
    first.counts()[bin] += second.counts()[bin];
  EXPECT_TRUE(std::ranges::equal(first.counts(), whole.counts()));
  EXPECT_EQ(whole.counts().size(), 512u);
  EXPECT_EQ(histogram_distance(first, other), histogram_distance(a, b, 3));
  EXPECT_GT(histogram_distance(a, b, 3), 0.0);
  EXPECT_EQ(histogram_distance(whole, whole), 0.0);
}

TEST(ColourHistogram, DisjointSetsAreOneApartAndBadInputThrows) {
  const std::vector<float> dark(30, 0.05f), light(60, 0.95f);
  EXPECT_EQ(histogram_distance(dark, light, 3), 1.0);
  EXPECT_THROW(ColourHistogram(5), Error);
  ColourHistogram h(3);
  EXPECT_THROW(h.add(std::vector<float>(4, 0.5f)), Error);
  EXPECT_THROW(histogram_distance(h, h), Error); // empty
}

} // namespace
} // namespace texsim::img
