#pragma once
// Timing helpers shared by the benchmarks: medians of repeated runs, and regions timed between
// barriers so every rank's share counts.
#include "par/comm.hpp"

#include <algorithm>
#include <fstream>
#include <functional>
#include <string>
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

inline double max_over_ranks(const par::Comm& comm, double value) {
  double result = 0;
  MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, MPI_MAX, comm.raw);
  return result;
}

/// Peak resident memory of this process (VmHWM), MB, maximum over ranks. Collective.
inline double peak_memory_mb(const par::Comm& comm) {
  std::ifstream status("/proc/self/status");
  double kilobytes = 0;
  for (std::string key; status >> key;) {
    if (key == "VmHWM:") {
      status >> kilobytes;
      break;
    }
  }
  return max_over_ranks(comm, kilobytes / 1024.0);
}

} // namespace texsim::bench
