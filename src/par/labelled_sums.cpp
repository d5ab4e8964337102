#include "par/labelled_sums.hpp"

#include "core/error.hpp"
#include "par/gather_to_root.hpp"
#include "par/reproducible_sum.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace texsim::par {

std::vector<LabelledTotal> labelled_sums_on_root(const Comm& comm,
                                                 std::span<const std::int64_t> labels,
                                                 std::span<const double> quantities,
                                                 std::size_t width) {
  TEXSIM_VERIFY(quantities.size() == width * labels.size(),
                "labelled sums: " << quantities.size() << " quantities for " << labels.size()
                                  << " items of width " << width);
  // One grid per quantity, from its bound and the item count over all ranks.
  std::vector<double> bounds(width, 0.0);
  for (std::size_t i = 0; i < labels.size(); ++i)
    for (std::size_t q = 0; q < width; ++q) {
      const double v = quantities[width * i + q];
      TEXSIM_VERIFY(std::isfinite(v), "labelled sums of a non-finite value " << v);
      bounds[q] = std::max(bounds[q], std::abs(v));
    }
  std::int64_t count = std::int64_t(labels.size());
  MPI_Allreduce(MPI_IN_PLACE, bounds.data(), int(width), MPI_DOUBLE, MPI_MAX, comm.raw);
  MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  std::vector<SliceGrids> grids;
  for (const double bound : bounds)
    grids.emplace_back(bound, count);

  // This rank's record per label: label, count, then width folded sums of 3 partial sums.
  const std::size_t record = 2 + 3 * width;
  std::vector<double> mine;
  {
    std::unordered_map<std::int64_t, std::size_t> record_of;
    for (std::size_t i = 0; i < labels.size(); ++i) {
      if (labels[i] < 0)
        continue;
      const auto [at, added] = record_of.try_emplace(labels[i], mine.size());
      if (added) {
        mine.resize(mine.size() + record, 0.0);
        mine[at->second] = double(labels[i]);
      }
      double* r = mine.data() + at->second;
      r[1] += 1;
      for (std::size_t q = 0; q < width; ++q) {
        FoldedSum sum{r[2 + 3 * q], r[3 + 3 * q], r[4 + 3 * q]};
        grids[q].add(quantities[width * i + q], sum);
        std::copy(sum.begin(), sum.end(), r + 2 + 3 * q);
      }
    }
  }
  const auto gathered = gather_to_root(comm, std::span<const double>(mine));
  std::vector<LabelledTotal> totals;
  if (!comm.is_root())
    return totals;
  std::vector<std::size_t> order(gathered.size() / record);
  for (std::size_t k = 0; k < order.size(); ++k)
    order[k] = k * record;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return gathered[a] < gathered[b]; });
  std::vector<FoldedSum> folded;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const double* r = gathered.data() + order[k];
    if (k == 0 || gathered[order[k - 1]] != r[0]) {
      totals.push_back({std::int64_t(r[0]), 0, std::vector<double>(width, 0.0)});
      folded.assign(width, FoldedSum{});
    }
    totals.back().count += std::int64_t(r[1]);
    for (std::size_t q = 0; q < width; ++q)
      for (std::size_t c = 0; c < 3; ++c)
        folded[q][c] += r[2 + 3 * q + c];
    // Partial sums add exactly in any order, so the running total is final after each record.
    for (std::size_t q = 0; q < width; ++q)
      totals.back().sums[q] = SliceGrids::total(folded[q]);
  }
  return totals;
}

} // namespace texsim::par
