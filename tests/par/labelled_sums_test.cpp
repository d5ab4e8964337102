// Per-label totals over ranks: the same bits as the whole set summed on one rank, for any split
// and order of the items, and exact against long-double sums where those are exact; labels with
// no items are absent, negative labels are left out.
#include "par/labelled_sums.hpp"

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

constexpr std::size_t kItems = 20011;
constexpr std::size_t kWidth = 3;

/// Item i: a label among 0, 7, 14, ..., 7 * 40 or -1 (left out), and values over many magnitudes
/// and both signs, where plain summation depends on the order.
std::int64_t label_of(std::size_t i) {
  const CounterRng rng(5, 0);
  const auto k = std::int64_t(rng.uniform(i, 0) * 42);
  return k == 41 ? -1 : 7 * k;
}

double value_of(std::size_t i, std::size_t q) {
  const CounterRng rng(5, 1);
  return rng.uniform(-1.0, 1.0, i, q) * std::ldexp(1.0, int(rng.uniform(i, q + 8) * 40) - 20);
}

std::vector<LabelledTotal> totals(const Comm& comm, bool reversed) {
  std::vector<std::int64_t> labels;
  std::vector<double> values;
  std::vector<std::size_t> items;
  for (std::size_t i = std::size_t(comm.rank); i < kItems; i += std::size_t(comm.size))
    items.push_back(i);
  if (reversed)
    std::reverse(items.begin(), items.end());
  for (const std::size_t i : items) {
    labels.push_back(label_of(i));
    for (std::size_t q = 0; q < kWidth; ++q)
      values.push_back(value_of(i, q));
  }
  return labelled_sums_on_root(comm, labels, values, kWidth);
}

TEST(LabelledSums, SameBitsAsOneRankForAnySplitAndOrder) {
  const Comm world = par::world();
  const auto split = totals(world, /*reversed=*/true);
  if (!world.is_root()) {
    EXPECT_TRUE(split.empty());
    return;
  }
  const auto serial = totals(self(), /*reversed=*/false);
  ASSERT_EQ(split.size(), serial.size());
  ASSERT_EQ(serial.size(), 41u) << "labels 0 ... 280 in steps of 7, -1 left out";
  for (std::size_t r = 0; r < serial.size(); ++r) {
    EXPECT_EQ(split[r].label, serial[r].label);
    EXPECT_EQ(split[r].label, std::int64_t(7 * r)) << "increasing label order";
    EXPECT_EQ(split[r].count, serial[r].count);
    for (std::size_t q = 0; q < kWidth; ++q)
      EXPECT_EQ(split[r].sums[q], serial[r].sums[q]) << "label " << serial[r].label;
  }
}

TEST(LabelledSums, AccurateAgainstAnExtendedPrecisionReference) {
  const auto serial = totals(self(), false);
  std::vector<long double> reference(41 * kWidth, 0.0L);
  std::vector<std::int64_t> counts(41, 0);
  for (std::size_t i = 0; i < kItems; ++i) {
    const std::int64_t label = label_of(i);
    if (label < 0)
      continue;
    ++counts[std::size_t(label / 7)];
    for (std::size_t q = 0; q < kWidth; ++q)
      reference[std::size_t(label / 7) * kWidth + q] += value_of(i, q);
  }
  for (std::size_t r = 0; r < serial.size(); ++r) {
    EXPECT_EQ(serial[r].count, counts[r]);
    for (std::size_t q = 0; q < kWidth; ++q)
      EXPECT_NEAR(serial[r].sums[q], double(reference[r * kWidth + q]),
                  4e-16 * std::abs(double(reference[r * kWidth + q])))
          << "within an ulp or two of the exact sum";
  }
}

TEST(LabelledSums, RefusesMismatchedWidthAndNonFiniteValues) {
  const std::vector<std::int64_t> labels{0, 1};
  EXPECT_THROW(labelled_sums_on_root(self(), labels, std::vector<double>{1, 2, 3}, 2), Error);
  EXPECT_THROW(labelled_sums_on_root(self(), labels, std::vector<double>{1, NAN}, 1), Error);
}

} // namespace
} // namespace texsim::par
