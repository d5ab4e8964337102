#include "core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace texsim {
namespace {

// Known-answer vectors for Philox4x32-10 published with Random123 (kat_vectors).
TEST(CounterRng, PhiloxMatchesPublishedKnownAnswers) {
  using Words = std::array<std::uint32_t, 4>;
  EXPECT_EQ(CounterRng::philox4x32_10({0, 0, 0, 0}, {0, 0}),
            (Words{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8}));
  EXPECT_EQ(CounterRng::philox4x32_10({0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff},
                                      {0xffffffff, 0xffffffff}),
            (Words{0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd}));
  EXPECT_EQ(CounterRng::philox4x32_10({0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344},
                                      {0xa4093822, 0x299f31d0}),
            (Words{0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1}));
}

TEST(CounterRng, SameKeySameNumberWhateverTheVisitOrder) {
  const CounterRng rng(42, 3);
  std::vector<double> forward, backward;
  for (std::uint64_t id = 0; id < 100; ++id)
    forward.push_back(rng.uniform(id, 7));
  for (std::uint64_t id = 100; id-- > 0;)
    backward.insert(backward.begin(), rng.uniform(id, 7));
  EXPECT_EQ(forward, backward);
}

TEST(CounterRng, SeedsStreamsStepsAndDrawsAreDistinct) {
  const CounterRng a(1, 0), b(2, 0), c(1, 1);
  EXPECT_NE(a.uniform(5, 0), b.uniform(5, 0));
  EXPECT_NE(a.uniform(5, 0), c.uniform(5, 0));
  EXPECT_NE(a.uniform(5, 0), a.uniform(5, 1));
  EXPECT_NE(a.uniform(5, 0, 0), a.uniform(5, 0, 1));
  EXPECT_NE(a.uniform(5, 0), a.uniform(std::uint64_t{5} << 32, 0));
}

TEST(CounterRng, UniformMomentsAndNormalMoments) {
  const CounterRng rng(2026, 1);
  const int n = 200000;
  double sum = 0, sum_sq = 0, normal_sum = 0, normal_sq = 0, lag_product = 0, previous = 0.5;
  for (int i = 0; i < n; ++i) {
    const double u = rng.uniform(i, 0);
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum_sq += u * u;
    lag_product += (u - 0.5) * (previous - 0.5);
    previous = u;
    const double z = rng.normal(i, 0);
    normal_sum += z;
    normal_sq += z * z;
  }
  // Standard errors: mean 1/sqrt(12 n) ~ 6.5e-4, so 5 sigma bounds.
  EXPECT_NEAR(sum / n, 0.5, 3.5e-3);
  EXPECT_NEAR(sum_sq / n - (sum / n) * (sum / n), 1.0 / 12.0, 2e-3);
  EXPECT_NEAR(lag_product / n, 0.0, 1e-3);
  EXPECT_NEAR(normal_sum / n, 0.0, 0.012);
  EXPECT_NEAR(normal_sq / n, 1.0, 0.02);
}

} // namespace
} // namespace texsim
