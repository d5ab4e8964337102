// gather_to_root: every rank's elements arrive on the root in rank order, whatever the message
// size (here down to 7 bytes, which splits elements across messages), whichever rank is root,
// and with ranks that contribute nothing; stream_to_root hands the parts over one by one;
// scatter_from_root sends each rank its part, the root making them one at a time, its own last.
#include "par/gather_to_root.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace texsim::par {
namespace {

/// Rank r contributes 5 r + (r % 2 ? 0 : 3) values r * 1000 + i: rank 1 contributes 5, and
/// every even rank three more, so sizes differ.
std::vector<std::int32_t> contribution(int rank) {
  std::vector<std::int32_t> values(static_cast<std::size_t>(5 * rank + (rank % 2 ? 0 : 3)));
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = rank * 1000 + static_cast<std::int32_t>(i);
  return values;
}

TEST(GatherToRoot, ConcatenatesInRankOrderWithAnyMessageSize) {
  const Comm comm = world();
  const auto mine = contribution(comm.rank);
  std::vector<std::int32_t> expected;
  for (int r = 0; r < comm.size; ++r) {
    const auto part = contribution(r);
    expected.insert(expected.end(), part.begin(), part.end());
  }
  for (const int root : {0, comm.size - 1})
    for (const std::size_t message : {std::size_t{7}, std::size_t{64}, kMaxGatherMessage}) {
      const auto all = gather_to_root(comm, std::span<const std::int32_t>(mine), root, message);
      if (comm.rank == root)
        EXPECT_EQ(all, expected) << "root " << root << ", messages of " << message << " bytes";
      else
        EXPECT_TRUE(all.empty());
    }
}

TEST(StreamToRoot, HandsEachRanksPartOverAloneInRankOrder) {
  const Comm comm = world();
  const auto mine = contribution(comm.rank);
  const int root = comm.size - 1;
  std::vector<int> ranks_seen;
  stream_to_root(
      comm, std::as_bytes(std::span<const std::int32_t>(mine)),
      [&](int rank, std::span<const std::byte> bytes) {
        ranks_seen.push_back(rank);
        const auto expected = contribution(rank);
        ASSERT_EQ(bytes.size(), expected.size() * sizeof(std::int32_t)) << "rank " << rank;
        std::vector<std::int32_t> values(expected.size());
        std::memcpy(values.data(), bytes.data(), bytes.size());
        EXPECT_EQ(values, expected) << "rank " << rank;
      },
      root, 7);
  std::vector<int> all_ranks;
  for (int r = 0; r < comm.size; ++r)
    all_ranks.push_back(r);
  EXPECT_EQ(ranks_seen, comm.rank == root ? all_ranks : std::vector<int>{});
}

TEST(ScatterFromRoot, EachRankGetsItsPartAndTheRootMakesThemOneAtATime) {
  const Comm comm = world();
  for (const int root : {0, comm.size - 1})
    for (const std::size_t message : {std::size_t{7}, std::size_t{64}, kMaxGatherMessage}) {
      std::vector<int> made; // on the root: the ranks whose parts it made, in order
      const auto mine = scatter_from_root<std::int32_t>(
          comm,
          [&](int rank) {
            made.push_back(rank);
            return contribution(rank);
          },
          root, message);
      EXPECT_EQ(mine, contribution(comm.rank)) << "root " << root << ", messages of " << message;
      if (comm.rank == root) {
        std::vector<int> expected;
        for (int r = 0; r < comm.size; ++r)
          if (r != root)
            expected.push_back(r);
        expected.push_back(root);
        EXPECT_EQ(made, expected);
      } else {
        EXPECT_TRUE(made.empty());
      }
    }
}

TEST(GatherToRoot, EmptyEverywhereGivesEmpty) {
  const Comm comm = world();
  const std::vector<double> none;
  EXPECT_TRUE(gather_to_root(comm, std::span<const double>(none)).empty());
}

} // namespace
} // namespace texsim::par
