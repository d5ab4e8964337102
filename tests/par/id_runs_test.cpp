// Arrays split into runs of ids over the ranks: allgather_runs completes a replicated array from
// every rank's run, and fetch_from_owners returns the values at any ids (any order, repeats,
// every owner, runs of different lengths and an empty one) in the order asked.
#include "core/rng.hpp"
#include "par/allgather_runs.hpp"
#include "par/fetch_from_owners.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace texsim::par {
namespace {

/// Uneven runs over the ranks: rank r holds 7 r + 3 ids, except rank 1, which holds none.
std::vector<std::int64_t> uneven_runs(int ranks) {
  std::vector<std::int64_t> offsets{0};
  for (int r = 0; r < ranks; ++r)
    offsets.push_back(offsets.back() + (r == 1 ? 0 : 7 * r + 3));
  return offsets;
}

/// The value of id `id`: two words that differ for every id.
std::array<std::int64_t, 2> value_of(std::int64_t id) {
  return {id * 31 + 5, -id};
}

TEST(IdRuns, OwnerOfFindsTheRunHoldingAnId) {
  const auto offsets = uneven_runs(4); // 0, 3, 3, 20, 44
  EXPECT_EQ(owner_of(offsets, 0), 0);
  EXPECT_EQ(owner_of(offsets, 2), 0);
  EXPECT_EQ(owner_of(offsets, 3), 2); // rank 1's run is empty
  EXPECT_EQ(owner_of(offsets, 19), 2);
  EXPECT_EQ(owner_of(offsets, 20), 3);
  EXPECT_EQ(owner_of(offsets, 43), 3);
}

TEST(IdRuns, AllgatherRunsCompletesTheArray) {
  const Comm comm = world();
  const auto offsets = uneven_runs(comm.size);
  std::vector<double> values(std::size_t(offsets.back()), -1.0);
  for (auto id = offsets[comm.rank]; id < offsets[comm.rank + 1]; ++id)
    values[std::size_t(id)] = 0.5 * double(id);
  allgather_runs(comm, offsets, values.data(), 1, MPI_DOUBLE);
  for (std::size_t id = 0; id < values.size(); ++id)
    EXPECT_EQ(values[id], 0.5 * double(id)) << "id " << id;
}

TEST(IdRuns, FetchFromOwnersAnswersInTheOrderAsked) {
  const Comm comm = world();
  const auto offsets = uneven_runs(comm.size);
  std::vector<std::array<std::int64_t, 2>> mine;
  for (auto id = offsets[comm.rank]; id < offsets[comm.rank + 1]; ++id)
    mine.push_back(value_of(id));
  // Each rank asks for its own list: random ids with repeats, and every id once at rank 0.
  const CounterRng rng(17, 3);
  std::vector<std::int64_t> ids;
  for (std::uint64_t k = 0; k < 50; ++k)
    ids.push_back(std::int64_t(rng.uniform(k, std::uint32_t(comm.rank)) * double(offsets.back())));
  if (comm.rank == 0)
    for (std::int64_t id = offsets.back() - 1; id >= 0; --id)
      ids.push_back(id);
  const auto values = fetch_from_owners(comm, offsets, std::span<const std::int64_t>(ids),
                                        std::span<const std::array<std::int64_t, 2>>(mine));
  ASSERT_EQ(values.size(), ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i)
    EXPECT_EQ(values[i], value_of(ids[i])) << "id " << ids[i];
  // Asking for nothing is fine on any rank.
  EXPECT_TRUE(fetch_from_owners(comm, offsets, std::span<const std::int64_t>(),
                                std::span<const std::array<std::int64_t, 2>>(mine))
                  .empty());
}

TEST(IdRuns, FetchFromOwnersRefusesAnIdOutsideTheArray) {
  const Comm comm = world();
  const auto offsets = uneven_runs(comm.size);
  std::vector<std::int32_t> mine(std::size_t(offsets[comm.rank + 1] - offsets[comm.rank]), 1);
  const std::vector<std::int64_t> ids{offsets.back()};
  EXPECT_ANY_THROW(fetch_from_owners(comm, offsets, std::span<const std::int64_t>(ids),
                                     std::span<const std::int32_t>(mine)));
}

} // namespace
} // namespace texsim::par
