#include "par/allgather_runs.hpp"

#include "core/error.hpp"

#include <climits>
#include <numeric>
#include <vector>

namespace texsim::par {

std::vector<std::int64_t> run_offsets(const Comm& comm, std::int64_t count) {
  std::vector<std::int64_t> offsets(std::size_t(comm.size) + 1, 0);
  MPI_Allgather(&count, 1, MPI_INT64_T, offsets.data() + 1, 1, MPI_INT64_T, comm.raw);
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  return offsets;
}

void allgather_runs(const Comm& comm, std::span<const std::int64_t> rank_offsets, void* values,
                    int width, MPI_Datatype type) {
  TEXSIM_VERIFY(rank_offsets.size() == std::size_t(comm.size) + 1,
                "allgather_runs: " << rank_offsets.size() << " rank offsets for " << comm.size
                                   << " ranks");
  TEXSIM_VERIFY(rank_offsets.back() * width <= INT_MAX,
                "allgather_runs: " << rank_offsets.back() << " elements of " << width
                                   << " items exceed MPI's int counts");
  std::vector<int> counts(std::size_t(comm.size)), displacements(std::size_t(comm.size));
  for (std::size_t r = 0; r < std::size_t(comm.size); ++r) {
    counts[r] = int((rank_offsets[r + 1] - rank_offsets[r]) * width);
    displacements[r] = int(rank_offsets[r] * width);
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, values, counts.data(), displacements.data(),
                 type, comm.raw);
}

} // namespace texsim::par
