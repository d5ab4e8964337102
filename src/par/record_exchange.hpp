#pragma once
/// Sending plain records to chosen ranks: every rank fills one outgoing list per destination and
/// receives what all ranks addressed to it, concatenated in source-rank order. The counts go first
/// (MPI_Alltoall), then the records as bytes (MPI_Alltoallv): the sparse, owner-computes exchange
/// behind halos and reductions to owners. allgather_records is the every-rank-to-every-rank case,
/// broadcast_records the rank-0-to-every-rank one.
#include "core/error.hpp"
#include "par/comm.hpp"

#include <mpi.h>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace texsim::par {

/// `outgoing[r]` goes to rank r (outgoing.size() == comm.size). Collective.
template <typename Record>
std::vector<Record> exchange_records(const Comm& comm,
                                     const std::vector<std::vector<Record>>& outgoing) {
  static_assert(std::is_trivially_copyable_v<Record>, "records travel as bytes");
  TEXSIM_VERIFY(int(outgoing.size()) == comm.size,
                "exchange_records: " << outgoing.size() << " lists for " << comm.size << " ranks");
  std::vector<int> send_counts(comm.size), send_offsets(comm.size), receive_counts(comm.size),
      receive_offsets(comm.size);
  std::vector<std::byte> send_bytes;
  for (int r = 0; r < comm.size; ++r) {
    const std::size_t bytes = outgoing[r].size() * sizeof(Record);
    TEXSIM_VERIFY(send_bytes.size() + bytes < std::size_t(INT32_MAX),
                  "exchange_records: more than 2 GiB to send from one rank");
    send_offsets[r] = int(send_bytes.size());
    send_counts[r] = int(bytes);
    const auto* first = reinterpret_cast<const std::byte*>(outgoing[r].data());
    send_bytes.insert(send_bytes.end(), first, first + bytes);
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm.raw);
  std::size_t total = 0;
  for (int r = 0; r < comm.size; ++r) {
    receive_offsets[r] = int(total);
    total += std::size_t(receive_counts[r]);
  }
  TEXSIM_VERIFY(total < std::size_t(INT32_MAX),
                "exchange_records: more than 2 GiB to receive on one rank");
  std::vector<Record> received(total / sizeof(Record));
  MPI_Alltoallv(send_bytes.data(), send_counts.data(), send_offsets.data(), MPI_BYTE,
                received.data(), receive_counts.data(), receive_offsets.data(), MPI_BYTE, comm.raw);
  return received;
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
