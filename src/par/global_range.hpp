#pragma once
/// The smallest and largest value over all ranks' spans, in one reduction.
#include "par/comm.hpp"

#include <mpi.h>

#include <algorithm>
#include <limits>
#include <span>

namespace texsim::par {

struct Range {
  double min = std::numeric_limits<double>::infinity();  ///< +inf when every span is empty
  double max = -std::numeric_limits<double>::infinity(); ///< -inf when every span is empty
};

/// Collective.
inline Range global_range(const Comm& comm, std::span<const double> values) {
  // min and -max reduce together with MPI_MIN.
  double local[2] = {std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::infinity()};
  for (const double v : values) {
    local[0] = std::min(local[0], v);
    local[1] = std::min(local[1], -v);
  }
  double global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MIN, comm.raw);
  return {global[0], -global[1]};
}

} // namespace texsim::par
