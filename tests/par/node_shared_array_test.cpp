// NodeSharedArray: every rank sees the concatenation of all ranks' parts in rank order, for the
// machine's own node layout and for emulated nodes of 1 and 2 ranks (so the leaders' broadcast
// runs on one machine), with messages split down to 7 bytes, parts written by the node's ranks in
// chunks down to 5 bytes, and ranks that contribute nothing;
// the ranks of a node map the same memory, aligned to a cache line.
#include "par/node_shared_array.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace texsim::par {
namespace {

/// Rank r contributes 3 r + (r % 2 ? 0 : 2) values r * 1000 + i (rank 1: 3 values, rank 0: 2).
std::vector<std::int64_t> contribution(int rank) {
  std::vector<std::int64_t> values(static_cast<std::size_t>(3 * rank + (rank % 2 ? 0 : 2)));
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = rank * 1000 + static_cast<std::int64_t>(i);
  return values;
}

std::vector<std::int64_t> expected_concatenation(int ranks) {
  std::vector<std::int64_t> all;
  for (int r = 0; r < ranks; ++r) {
    const auto part = contribution(r);
    all.insert(all.end(), part.begin(), part.end());
  }
  return all;
}

TEST(NodeLayout, EmulatedNodesGroupConsecutiveRanks) {
  const Comm comm = world();
  for (const int per_node : {1, 2}) {
    const auto layout = NodeLayout::make(comm, per_node);
    EXPECT_EQ(layout->node_count, (comm.size + per_node - 1) / per_node);
    for (int r = 0; r < comm.size; ++r)
      EXPECT_EQ(layout->node_of_rank[std::size_t(r)], r / per_node) << "rank " << r;
    EXPECT_EQ(layout->node.rank, comm.rank % per_node);
    EXPECT_EQ(layout->leaders.raw != MPI_COMM_NULL, comm.rank % per_node == 0);
  }
  // One machine: all ranks share one node.
  const auto machine = NodeLayout::make(comm);
  EXPECT_EQ(machine->node_count, 1);
  EXPECT_EQ(machine->node.size, comm.size);
}

TEST(NodeSharedArray, ConcatenatesInRankOrderOnEveryNodeLayout) {
  const Comm comm = world();
  const auto mine = contribution(comm.rank);
  const auto expected = expected_concatenation(comm.size);
  for (const int per_node : {0, 1, 2}) {
    const auto layout = NodeLayout::make(comm, per_node);
    for (const std::size_t message : {std::size_t{7}, std::size_t{1} << 30})
      for (const std::size_t chunk : {std::size_t{5}, std::size_t{16}, kNodeChunk}) {
        const NodeSharedBytes bytes =
            node_shared_concatenation(layout, std::as_bytes(std::span(mine)), message, chunk);
        const NodeSharedArray<std::int64_t> all(bytes);
        EXPECT_EQ(std::vector<std::int64_t>(all.values().begin(), all.values().end()), expected)
            << per_node << " ranks per node, messages of " << message << " bytes, chunks of "
            << chunk;
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(all.data()) % 64, 0u);
      }
  }
}

TEST(NodeSharedArray, FromRootReachesEveryNode) {
  const Comm comm = world();
  const std::vector<double> values{1.5, -2.0, 3.25};
  const std::vector<double> garbage{9.0};
  for (const int per_node : {0, 1}) {
    const auto root = comm.size - 1;
    const auto shared = NodeSharedArray<double>::from_root(
        NodeLayout::make(comm, per_node), comm.rank == root ? values : garbage, root);
    EXPECT_EQ(std::vector<double>(shared.values().begin(), shared.values().end()), values);
  }
}

TEST(NodeSharedBytes, RanksOfANodeMapTheSameMemory) {
  const Comm comm = world();
  const auto layout = NodeLayout::make(comm);
  const NodeSharedBytes shared(layout, sizeof(std::int32_t) * std::size_t(layout->node.size));
  // Each rank writes its own slot, then reads everybody's: only shared memory shows them all.
  auto* slots = reinterpret_cast<std::int32_t*>(shared.bytes().data());
  slots[layout->node.rank] = 100 + comm.rank;
  shared.synchronise();
  for (int r = 0; r < layout->node.size; ++r)
    EXPECT_EQ(slots[r], 100 + r) << "slot of node rank " << r;
  shared.synchronise(); // nobody frees the window while another rank still reads
}

} // namespace
} // namespace texsim::par
