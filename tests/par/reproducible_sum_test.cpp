// Reproducible sums: the same bits however the values are split over ranks and ordered, and
// accurate against an exact reference.
#include "par/reproducible_sum.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace texsim::par {
namespace {

Comm self() {
  return {MPI_COMM_SELF, 0, 1};
}

/// Values over many magnitudes and both signs, where plain summation depends on the order.
std::vector<double> wide_values(std::size_t count) {
  const CounterRng rng(11, 0);
  std::vector<double> values(count);
  for (std::size_t i = 0; i < count; ++i)
    values[i] = rng.uniform(-1.0, 1.0, i, 0) * std::ldexp(1.0, int(rng.uniform(i, 1) * 40) - 20);
  return values;
}

TEST(ReproducibleSum, SameBitsForAnySplitAndOrder) {
  const Comm world = par::world();
  const std::vector<double> all = wide_values(10007);
  const double serial = reproducible_sum(self(), all);
  // This rank's share: a strided split (every size-th value), then reversed.
  std::vector<double> mine;
  for (std::size_t i = std::size_t(world.rank); i < all.size(); i += std::size_t(world.size))
    mine.push_back(all[i]);
  std::reverse(mine.begin(), mine.end());
  EXPECT_EQ(reproducible_sum(world, mine), serial) << "on " << world.size << " ranks";
  std::vector<double> shuffled = all;
  std::reverse(shuffled.begin(), shuffled.begin() + 5000);
  std::rotate(shuffled.begin(), shuffled.begin() + 333, shuffled.end());
  EXPECT_EQ(reproducible_sum(self(), shuffled), serial);
  // Plain summation does depend on the order here, so the test can tell.
  double forward = 0.0, backward = 0.0;
  for (const double v : all)
    forward += v;
  for (auto v = all.rbegin(); v != all.rend(); ++v)
    backward += *v;
  EXPECT_NE(forward, backward);
}

TEST(ReproducibleSum, AccurateAgainstAnExactReference) {
  // Integers times a power of two sum exactly in long double when they are small enough: the
  // reference. Cancelling values test that the slices keep the small remainder.
  std::vector<double> values;
  long double exact = 0.0L;
  for (int i = 0; i < 2000; ++i) {
    const double v = std::ldexp(double((i * 7919) % 1000 - 500), -30) + (i % 2 ? 1e6 : -1e6);
    values.push_back(v);
    exact += static_cast<long double>(v);
  }
  EXPECT_EQ(reproducible_sum(self(), values), static_cast<double>(exact));
  EXPECT_EQ(reproducible_sum(self(), std::vector<double>{}), 0.0);
  EXPECT_EQ(reproducible_sum(self(), std::vector<double>(5, 0.0)), 0.0);
  EXPECT_EQ(reproducible_sum(self(), std::vector<double>{-3.5}), -3.5);
  EXPECT_THROW(reproducible_sum(self(), std::vector<double>{1.0, NAN}), Error);
}

TEST(ReproducibleSum, PartialSumsOfBinsAddUpExactly) {
  // Values binned (regions), each bin summed in parts that are added component by component:
  // the bin totals equal the bins summed whole.
  const std::vector<double> values = wide_values(3000);
  const SliceGrids grids = slice_grids_for(self(), values);
  FoldedSum whole{}, first{}, second{};
  for (std::size_t i = 0; i < values.size(); ++i) {
    grids.add(values[i], whole);
    grids.add(values[i], i % 3 ? first : second);
  }
  for (std::size_t k = 0; k < first.size(); ++k)
    first[k] += second[k];
  EXPECT_EQ(SliceGrids::total(first), SliceGrids::total(whole));
  EXPECT_EQ(SliceGrids::total(whole), reproducible_sum(self(), values));
}

} // namespace
} // namespace texsim::par
