#pragma once
/// Sending plain records to chosen ranks: every rank fills one outgoing list per destination and
/// receives what all ranks addressed to it, concatenated in source-rank order. The counts go first
/// (MPI_Alltoall), then the records as bytes (MPI_Alltoallv): the sparse, owner-computes exchange
/// behind halos and reductions to owners. allgather_records is the every-rank-to-every-rank case,
/// broadcast_records the rank-0-to-every-rank one.
#include "core/error.hpp"
#include "par/comm.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace texsim::par {

namespace detail {
/// exchange_records' work. A rank's own list is copied straight into the result, never through
/// the send buffer or MPI; with `release`, each list is freed as soon as it is packed, and the own
/// list becomes the result when nothing else arrives.
template <typename Record>
std::vector<Record> exchange(const Comm& comm, std::vector<std::vector<Record>>& outgoing,
                             bool release) {
  static_assert(std::is_trivially_copyable_v<Record>, "records travel as bytes");
  TEXSIM_VERIFY(int(outgoing.size()) == comm.size,
                "exchange_records: " << outgoing.size() << " lists for " << comm.size << " ranks");
  std::vector<int> send_counts(comm.size), send_offsets(comm.size), receive_counts(comm.size),
      receive_offsets(comm.size);
  std::size_t send_total = 0;
  for (int r = 0; r < comm.size; ++r)
    if (r != comm.rank)
      send_total += outgoing[r].size() * sizeof(Record);
  TEXSIM_VERIFY(send_total < std::size_t(INT32_MAX),
                "exchange_records: more than 2 GiB to send from one rank");
  std::vector<std::byte> send_bytes;
  send_bytes.reserve(send_total);
  for (int r = 0; r < comm.size; ++r) {
    send_offsets[r] = int(send_bytes.size());
    if (r == comm.rank)
      continue;
    const std::size_t bytes = outgoing[r].size() * sizeof(Record);
    send_counts[r] = int(bytes);
    const auto* first = reinterpret_cast<const std::byte*>(outgoing[r].data());
    send_bytes.insert(send_bytes.end(), first, first + bytes);
    if (release)
      outgoing[r] = {};
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm.raw);
  const std::size_t own_bytes = outgoing[comm.rank].size() * sizeof(Record);
  std::size_t total = 0;
  for (int r = 0; r < comm.size; ++r) {
    receive_offsets[r] = int(total);
    total += r == comm.rank ? own_bytes : std::size_t(receive_counts[r]);
  }
  TEXSIM_VERIFY(total < std::size_t(INT32_MAX),
                "exchange_records: more than 2 GiB to receive on one rank");
  std::vector<Record> received;
  if (release && total == own_bytes) { // nothing arrives from elsewhere: the own list is the result
    received = std::move(outgoing[comm.rank]);
  } else {
    received.resize(total / sizeof(Record));
    std::copy(outgoing[comm.rank].begin(), outgoing[comm.rank].end(),
              received.begin() + receive_offsets[comm.rank] / std::ptrdiff_t(sizeof(Record)));
    if (release)
      outgoing[comm.rank] = {};
  }
  MPI_Alltoallv(send_bytes.data(), send_counts.data(), send_offsets.data(), MPI_BYTE,
                received.data(), receive_counts.data(), receive_offsets.data(), MPI_BYTE, comm.raw);
  return received;
}
} // namespace detail

/// `outgoing[r]` goes to rank r (outgoing.size() == comm.size). Collective.
template <typename Record>
std::vector<Record> exchange_records(const Comm& comm,
                                     const std::vector<std::vector<Record>>& outgoing) {
  // Not released, so the lists are only read.
  return detail::exchange(comm, const_cast<std::vector<std::vector<Record>>&>(outgoing), false);
}

/// The same, freeing each list as soon as it is packed: the lists and the send buffer are not
/// held whole at once. `outgoing` is left empty. Collective.
template <typename Record>
std::vector<Record> exchange_records(const Comm& comm,
                                     std::vector<std::vector<Record>>&& outgoing) {
  auto result = detail::exchange(comm, outgoing, true);
  outgoing.clear();
  return result;
}

/// Every rank's `local` records on every rank, concatenated in rank order. Collective.
template <typename Record>
std::vector<Record> allgather_records(const Comm& comm, const std::vector<Record>& local) {
  static_assert(std::is_trivially_copyable_v<Record>, "records travel as bytes");
  TEXSIM_VERIFY(local.size() * sizeof(Record) < std::size_t(INT32_MAX),
                "allgather_records: more than 2 GiB from one rank");
  const int bytes = int(local.size() * sizeof(Record));
  std::vector<int> counts(comm.size), offsets(comm.size);
  MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm.raw);
  std::size_t total = 0;
  for (int r = 0; r < comm.size; ++r) {
    offsets[r] = int(total);
    total += std::size_t(counts[r]);
  }
  TEXSIM_VERIFY(total < std::size_t(INT32_MAX),
                "allgather_records: more than 2 GiB to receive on one rank");
  std::vector<Record> all(total / sizeof(Record));
  MPI_Allgatherv(local.data(), bytes, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE,
                 comm.raw);
  return all;
}

/// Rank 0's `records` on every rank (the others' are replaced). Collective.
template <typename Record> void broadcast_records(const Comm& comm, std::vector<Record>& records) {
  static_assert(std::is_trivially_copyable_v<Record>, "records travel as bytes");
  std::int64_t count = std::int64_t(records.size());
  MPI_Bcast(&count, 1, MPI_INT64_T, 0, comm.raw);
  TEXSIM_VERIFY(std::size_t(count) * sizeof(Record) < std::size_t(INT32_MAX),
                "broadcast_records: more than 2 GiB");
  records.resize(std::size_t(count));
  MPI_Bcast(records.data(), int(records.size() * sizeof(Record)), MPI_BYTE, 0, comm.raw);
}

} // namespace texsim::par
