#pragma once
/// How far apart the colour distributions of two sets of pixels (or voxels, or vertices) are: the
/// quality figure texture synthesis reports beside the neighbourhood error.
#include <cstdint>
#include <span>
#include <vector>

namespace texsim::img {

/// The joint histogram of colours of `channels` (1 to 4) values, 8 bins per channel over [0, 1]
/// (values clamped), as element counts: counts of parts of a set (e.g. each rank's share of a
/// volume) add up to the counts of the whole, exactly.
class ColourHistogram {
public:
  /// Throws Error unless 1 <= channels <= 4.
  explicit ColourHistogram(int channels);

  /// Counts every element of `values` (`channels` interleaved values each; a whole number of
  /// elements, else Error).
  void add(std::span<const float> values);

  int channels() const { return channels_; }
  /// The 8^channels bin counts, the first channel's bin most significant.
  std::span<std::int64_t> counts() { return counts_; }
  std::span<const std::int64_t> counts() const { return counts_; }

private:
  int channels_;
  std::vector<std::int64_t> counts_;
};

/// Half the L1 distance between the normalised histograms: 0 for the same distribution, 1 for
/// disjoint ones. Throws Error if their channels differ or either is empty.
double histogram_distance(const ColourHistogram& a, const ColourHistogram& b);

/// The same for two element lists of `channels` interleaved values (at least one element each).
double histogram_distance(std::span<const float> a, std::span<const float> b, int channels);

} // namespace texsim::img
