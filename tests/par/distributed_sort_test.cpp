// distributed_sort: the runs of all ranks, in rank order, are the serial sort of all records; rank
// r holds positions [ceil(r n / p), ceil((r + 1) n / p)); whether the records start spread evenly,
// all on one rank, or skewed, with many equal keys (ties broken by id), at 1, 2 and 3 ranks.
#include "core/rng.hpp"
#include "par/distributed_sort.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>

namespace texsim::par {
namespace {

struct Keyed {
  std::uint64_t key;
  std::int64_t id;
};

bool before(const Keyed& a, const Keyed& b) {
  return std::tie(a.key, a.id) < std::tie(b.key, b.id);
}

/// Record `id` of n: keys from 0 to `distinct` - 1, so many are equal when distinct is small.
Keyed record(std::int64_t id, std::uint64_t distinct) {
  const CounterRng rng(11, 4);
  return {std::uint64_t(rng.uniform(std::uint64_t(id), 0) * double(distinct)), id};
}

/// Sorts n records of which rank r starts with those `holds(id)` says; checks the result.
template <typename Holds> void check(std::int64_t n, std::uint64_t distinct, Holds holds) {
  const Comm comm = world();
  std::vector<Keyed> mine, all;
  for (std::int64_t id = 0; id < n; ++id) {
    all.push_back(record(id, distinct));
    if (holds(id))
      mine.push_back(all.back());
  }
  const auto run = distributed_sort(comm, mine, before);
  std::sort(all.begin(), all.end(), before);
  const auto p = std::int64_t(comm.size), r = std::int64_t(comm.rank);
  const std::int64_t first = (r * n + p - 1) / p, last = ((r + 1) * n + p - 1) / p;
  ASSERT_EQ(std::int64_t(run.size()), last - first);
  for (std::size_t k = 0; k < run.size(); ++k) {
    ASSERT_EQ(run[k].key, all[std::size_t(first) + k].key);
    ASSERT_EQ(run[k].id, all[std::size_t(first) + k].id);
  }
}

TEST(DistributedSort, EvenlySpreadRecordsWithManyTies) {
  const Comm comm = world();
  check(10007, 50, [&](std::int64_t id) { return id % comm.size == comm.rank; });
}

TEST(DistributedSort, AllRecordsStartOnTheLastRank) {
  const Comm comm = world();
  check(5000, 1u << 30, [&](std::int64_t) { return comm.rank == comm.size - 1; });
}

TEST(DistributedSort, SkewedStartAndFewerRecordsThanRanksSquared) {
  const Comm comm = world();
  check(7, 3,
        [&](std::int64_t id) { return id < 2 ? comm.rank == 0 : comm.rank == 1 % comm.size; });
  check(0, 3, [](std::int64_t) { return true; });
}

} // namespace
} // namespace texsim::par
