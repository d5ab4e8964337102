#pragma once
/// How far apart the colour distributions of two sets of pixels (or voxels, or vertices) are: the
/// quality figure texture synthesis reports beside the neighbourhood error.
#include <span>

namespace texsim::img {

/// Half the L1 distance between the normalised joint histograms of `a` and `b` (8 bins per
/// channel over [0, 1], values clamped): 0 for the same distribution, 1 for disjoint ones. Both
/// hold `channels` (1 to 4) interleaved values per element and at least one element. Throws
/// Error otherwise.
double histogram_distance(std::span<const float> a, std::span<const float> b, int channels);

} // namespace texsim::img
