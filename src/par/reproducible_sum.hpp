#pragma once
/// Sums of doubles whose bits do not depend on how the values are split over ranks or in what
/// order they are added: figures such as a pattern's mean threshold or a region's area must be
/// the same at -n 1 and -n 64. Each value is cut into slices on fixed binary grids (pre-rounding,
/// as in Demmel and Nguyen's reproducible summation): on its grid a slice is an exact multiple
/// of the grid's unit, so any sum of slices is exact, hence independent of the order. The grids
/// follow from a bound on |value| and on the number of values; what is left below the finest
/// grid (about 2^-150 of bound x count) is dropped.
#include "par/comm.hpp"

#include <array>
#include <cstdint>
#include <span>

namespace texsim::par {

/// Partial sums of slices, one per grid, coarsest first.
using FoldedSum = std::array<double, 3>;

class SliceGrids {
public:
  /// Grids for at most `count` values of magnitude at most `bound` (finite; 0 gives sums of 0).
  SliceGrids(double bound, std::int64_t count);

  /// Adds `value` (|value| <= bound) to `sum`.
  void add(double value, FoldedSum& sum) const;
  /// The total of `sum`'s partial sums, added coarsest first. Partial sums of different values
  /// may be added component by component (exactly) before.
  static double total(const FoldedSum& sum);

private:
  FoldedSum extractor_{};
};

/// The grids for every rank's values together: bound and count over all ranks. Collective.
SliceGrids slice_grids_for(const Comm& comm, std::span<const double> values);

/// Adds the partial sums of every rank (exact). Collective.
FoldedSum sum_over_ranks(const Comm& comm, const FoldedSum& mine);

/// The sum of every rank's `values`: the same bits for any split over ranks and any order.
/// Collective.
double reproducible_sum(const Comm& comm, std::span<const double> values);

} // namespace texsim::par
