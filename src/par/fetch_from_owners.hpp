#pragma once
/// Reading entries of an array split into runs over the ranks (par/id_runs.hpp) that other ranks
/// own: the halo reads of data kept per run, such as a mesh level's per-vertex values.
#include "par/comm.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

namespace texsim::par {

/// The values at `ids` (any order, repeats allowed; 0 <= id < rank_offsets.back()) of the array
/// whose run [rank_offsets[r], rank_offsets[r + 1]) rank r holds as `mine`: each distinct id is
/// asked of its owner once, and the answers come back in the order of `ids`. Collective.
template <typename Value>
std::vector<Value> fetch_from_owners(const Comm& comm, std::span<const std::int64_t> rank_offsets,
                                     std::span<const std::int64_t> ids,
                                     std::span<const Value> mine) {
  static_assert(std::is_trivially_copyable_v<Value>, "values travel as bytes");
  const std::int64_t first = rank_offsets[std::size_t(comm.rank)];
  TEXSIM_VERIFY(std::int64_t(mine.size()) == rank_offsets[std::size_t(comm.rank) + 1] - first,
                "fetch_from_owners: " << mine.size() << " values for a run of "
                                      << rank_offsets[std::size_t(comm.rank) + 1] - first);
  std::vector<std::int64_t> distinct(ids.begin(), ids.end());
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  TEXSIM_VERIFY(distinct.empty() ||
                    (distinct.front() >= 0 && distinct.back() < rank_offsets.back()),
                "fetch_from_owners: an id outside [0, " << rank_offsets.back() << ")");
  // Requests go out per owner in ascending id order and the answers return in the same order,
  // grouped by owner in rank order: that is `distinct`'s order.
  std::vector<std::vector<std::int64_t>> requests(std::size_t(comm.size));
  for (const std::int64_t id : distinct)
    requests[std::size_t(owner_of(rank_offsets, id))].push_back(id);
  std::vector<int> asked(std::size_t(comm.size));
  for (std::size_t r = 0; r < requests.size(); ++r)
    asked[r] = int(requests[r].size());
  const auto asked_of_me = exchange_records(comm, std::move(requests));
  // How many ids each rank asked: the answers go back to them in the same order.
  std::vector<int> counts(std::size_t(comm.size));
  MPI_Alltoall(asked.data(), 1, MPI_INT, counts.data(), 1, MPI_INT, comm.raw);
  std::vector<std::vector<Value>> answers(std::size_t(comm.size));
  std::size_t next = 0;
  for (std::size_t r = 0; r < answers.size(); ++r)
    for (int k = 0; k < counts[r]; ++k)
      answers[r].push_back(mine[std::size_t(asked_of_me[next++] - first)]);
  const auto values = exchange_records(comm, std::move(answers));
  std::vector<Value> result;
  result.reserve(ids.size());
  for (const std::int64_t id : ids)
    result.push_back(values[std::size_t(std::lower_bound(distinct.begin(), distinct.end(), id) -
                                        distinct.begin())]);
  return result;
}

} // namespace texsim::par
