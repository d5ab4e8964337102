#pragma once
/// The median of values spread over the ranks.
#include "par/comm.hpp"

#include <span>

namespace texsim::par {

/// Median of the union of every rank's `values` (the mean of the two middle values for an even
/// count; NaN when every span is empty). Gathers the values on rank 0, which selects and
/// broadcasts: O(total count) memory on rank 0 only, meant for per-cell or per-vertex scalars
/// reported once. The same on every rank. Collective.
double global_median(const Comm& comm, std::span<const double> values);

} // namespace texsim::par
