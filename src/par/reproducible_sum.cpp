#include "par/reproducible_sum.hpp"

#include "core/error.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>

namespace texsim::par {

SliceGrids::SliceGrids(double bound, std::int64_t count) {
  TEXSIM_VERIFY(std::isfinite(bound) && bound >= 0.0 && count >= 0,
                "reproducible sum: bound " << bound << " and count " << count
                                           << " must be finite and non-negative");
  if (bound == 0.0 || count == 0)
    return; // every extractor 0: all slices are 0
  // Grid k has unit u_k = 2^(e_k - 52), with 2^e_k >= 2 count bound_k: the extractor 1.5 * 2^e_k
  // plus a value keeps the binade [2^e_k, 2^(e_k + 1)), so (extractor + v) - extractor is v
  // rounded to the grid, exactly, and count slices add up to less than 2^53 units. What is left,
  // at most u_k / 2, is sliced on the next grid.
  double remaining_bound = bound;
  for (double& extractor : extractor_) {
    const int e = static_cast<int>(std::ceil(std::log2(2.0 * double(count) * remaining_bound)));
    extractor = 1.5 * std::ldexp(1.0, e);
    remaining_bound = std::ldexp(1.0, e - 53);
  }
}

void SliceGrids::add(double value, FoldedSum& sum) const {
  for (std::size_t k = 0; k < extractor_.size(); ++k) {
    if (extractor_[k] == 0.0)
      return;
    // volatile: the compiler must not fold (x + v) - x into v.
    volatile double shifted = extractor_[k] + value;
    const double slice = shifted - extractor_[k];
    sum[k] += slice;
    value -= slice;
  }
}

double SliceGrids::total(const FoldedSum& sum) {
  double total = 0.0;
  for (const double part : sum)
    total += part;
  return total;
}

SliceGrids slice_grids_for(const Comm& comm, std::span<const double> values) {
  double bound = 0.0;
  for (const double v : values) {
    TEXSIM_VERIFY(std::isfinite(v), "reproducible sum of a non-finite value " << v);
    bound = std::max(bound, std::abs(v));
  }
  std::int64_t count = static_cast<std::int64_t>(values.size());
  MPI_Allreduce(MPI_IN_PLACE, &bound, 1, MPI_DOUBLE, MPI_MAX, comm.raw);
  MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  return SliceGrids(bound, count);
}

FoldedSum sum_over_ranks(const Comm& comm, const FoldedSum& mine) {
  FoldedSum all = mine;
  MPI_Allreduce(MPI_IN_PLACE, all.data(), static_cast<int>(all.size()), MPI_DOUBLE, MPI_SUM,
                comm.raw);
  return all;
}

double reproducible_sum(const Comm& comm, std::span<const double> values) {
  const SliceGrids grids = slice_grids_for(comm, values);
  FoldedSum sum{};
  for (const double v : values)
    grids.add(v, sum);
  return SliceGrids::total(sum_over_ranks(comm, sum));
}

} // namespace texsim::par
