#include "img/colour_histogram.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace texsim::img {
namespace {

constexpr int kBins = 8;

std::vector<double> histogram(std::span<const float> values, int channels, std::size_t bins) {
  std::vector<double> frequency(bins, 0.0);
  const std::size_t count = values.size() / std::size_t(channels);
  for (std::size_t e = 0; e < count; ++e) {
    std::size_t bin = 0;
    for (int c = 0; c < channels; ++c) {
      const float value = values[e * std::size_t(channels) + std::size_t(c)];
      const int level =
          std::min(kBins - 1, static_cast<int>(std::clamp(value, 0.0f, 1.0f) * kBins));
      bin = bin * kBins + std::size_t(level);
    }
    frequency[bin] += 1.0;
  }
  for (double& f : frequency)
    f /= double(count);
  return frequency;
}

} // namespace

double histogram_distance(std::span<const float> a, std::span<const float> b, int channels) {
  TEXSIM_VERIFY(channels >= 1 && channels <= 4 && !a.empty() && !b.empty() &&
                    a.size() % std::size_t(channels) == 0 && b.size() % std::size_t(channels) == 0,
                "histogram_distance needs 1 to 4 channels and whole, non-empty element lists, got "
                    << channels << " channels, " << a.size() << " and " << b.size() << " values");
  std::size_t bins = 1;
  for (int c = 0; c < channels; ++c)
    bins *= kBins;
  const auto pa = histogram(a, channels, bins), pb = histogram(b, channels, bins);
  double total = 0.0;
  for (std::size_t bin = 0; bin < bins; ++bin)
    total += std::abs(pa[bin] - pb[bin]);
  return 0.5 * total;
}

} // namespace texsim::img
