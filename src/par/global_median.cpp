#include "par/global_median.hpp"

#include <mpi.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <vector>

namespace texsim::par {

double global_median(const Comm& comm, std::span<const double> values) {
  const int local_count = int(values.size());
  std::vector<int> counts(comm.rank == 0 ? std::size_t(comm.size) : 0);
  MPI_Gather(&local_count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm.raw);
  std::vector<int> offsets(counts.size(), 0);
  if (!counts.empty())
    std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
  std::vector<double> all(comm.rank == 0 ? std::size_t(offsets.back() + counts.back()) : 0);
  MPI_Gatherv(values.data(), local_count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
              MPI_DOUBLE, 0, comm.raw);
  double median = std::numeric_limits<double>::quiet_NaN();
  if (comm.rank == 0 && !all.empty()) {
    const auto middle = all.begin() + std::ptrdiff_t(all.size() / 2);
    std::nth_element(all.begin(), middle, all.end());
    median = *middle;
    if (all.size() % 2 == 0)
      median = 0.5 * (median + *std::max_element(all.begin(), middle));
  }
  MPI_Bcast(&median, 1, MPI_DOUBLE, 0, comm.raw);
  return median;
}

} // namespace texsim::par
