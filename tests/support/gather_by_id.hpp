#pragma once
// Test helper: values owned by the ranks, keyed by global ids 0..n-1, assembled on every rank in id
// order (to compare a distributed result with a serial one, or bit patterns across rank counts).
#include "par/comm.hpp"

#include <mpi.h>

#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

namespace texsim::test {

/// `components` values per id. Collective.
inline std::vector<double> gather_by_id(const par::Comm& comm, std::span<const std::int64_t> ids,
                                        std::span<const double> values, int components = 1) {
  const int count = int(ids.size());
  std::vector<int> counts(comm.size), offsets(comm.size, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm.raw);
  std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
  const int total = offsets.back() + counts.back();
  std::vector<std::int64_t> all_ids(total);
  MPI_Allgatherv(ids.data(), count, MPI_INT64_T, all_ids.data(), counts.data(), offsets.data(),
                 MPI_INT64_T, comm.raw);
  for (int r = 0; r < comm.size; ++r) {
    counts[r] *= components;
    offsets[r] *= components;
  }
  std::vector<double> all_values(std::size_t(total) * components);
  MPI_Allgatherv(values.data(), count * components, MPI_DOUBLE, all_values.data(), counts.data(),
                 offsets.data(), MPI_DOUBLE, comm.raw);
  std::vector<double> by_id(all_values.size());
  for (int k = 0; k < total; ++k)
    for (int c = 0; c < components; ++c)
      by_id[std::size_t(all_ids[k]) * components + c] = all_values[std::size_t(k) * components + c];
  return by_id;
}

inline par::Comm self_comm() {
  par::Comm comm;
  comm.raw = MPI_COMM_SELF;
  return comm;
}

} // namespace texsim::test
