#pragma once
/// Sorting records spread over ranks without gathering them: a sample sort (regular samples of
/// every rank's sorted records pick p - 1 splitters, one all-to-all moves each record to its
/// bucket) followed by a rebalance to even runs, so that rank r ends with the records at sorted
/// positions [ceil(r n / p), ceil((r + 1) n / p)): position g goes to rank floor(g p / n). Per rank
/// O(n / p) records plus an O(p^2) table of samples; the result depends only on the records and
/// the order, not on how they were spread.
#include "par/comm.hpp"
#include "par/record_exchange.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace texsim::par {

/// `less` must be a strict total order on the records (no two records equivalent), so that the
/// sorted sequence is unique. Returns this rank's run, sorted. Collective.
template <typename Record, typename Less>
std::vector<Record> distributed_sort(const Comm& comm, std::vector<Record> records, Less less) {
  std::sort(records.begin(), records.end(), less);
  if (comm.size == 1)
    return records;

  // p - 1 regular samples of each rank's records; every rank sorts the same table and takes
  // every p-th sample as a splitter.
  const std::size_t p = std::size_t(comm.size);
  std::vector<Record> samples;
  for (std::size_t k = 1; k < p && !records.empty(); ++k)
    samples.push_back(records[k * records.size() / p]);
  auto table = allgather_records(comm, samples);
  std::sort(table.begin(), table.end(), less);
  std::vector<Record> splitters;
  for (std::size_t k = 1; k < p && !table.empty(); ++k)
    splitters.push_back(table[k * table.size() / p]);

  // Bucket b holds the records before splitter b (and from splitter b - 1 on).
  std::vector<std::vector<Record>> buckets(p);
  auto first = records.begin();
  for (std::size_t b = 0; b < p; ++b) {
    const auto last = b < splitters.size()
                          ? std::lower_bound(first, records.end(), splitters[b], less)
                          : records.end();
    buckets[b].assign(first, last);
    first = last;
  }
  records = {};
  auto bucket = exchange_records(comm, buckets);
  buckets = {};
  std::sort(bucket.begin(), bucket.end(), less);

  // Rebalance: the bucket's first record sits at the sum of the lower buckets' sizes.
  std::int64_t count = std::int64_t(bucket.size()), before = 0, total = 0;
  MPI_Exscan(&count, &before, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  if (comm.rank == 0)
    before = 0;
  MPI_Allreduce(&count, &total, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  std::vector<std::vector<Record>> runs(p);
  for (std::size_t k = 0; k < bucket.size(); ++k) {
    const std::int64_t position = before + std::int64_t(k);
    runs[std::size_t(position * std::int64_t(p) / total)].push_back(bucket[k]);
  }
  // Received in source-rank order, which is sorted order.
  return exchange_records(comm, runs);
}

} // namespace texsim::par
