#pragma once
// Timing helpers shared by the benchmarks: medians of repeated runs, and regions timed between
// barriers so every rank's share counts.
#include "par/comm.hpp"

#include <algorithm>
#include <functional>
#include <vector>

namespace texsim::bench {

inline double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

/// Wall time of `work` from a barrier before it to a barrier after it. Collective.
inline double timed(const par::Comm& comm, const std::function<void()>& work) {
  MPI_Barrier(comm.raw);
  const double start = MPI_Wtime();
  work();
  MPI_Barrier(comm.raw);
  return MPI_Wtime() - start;
}

} // namespace texsim::bench
