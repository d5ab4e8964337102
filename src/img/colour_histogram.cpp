#include "img/colour_histogram.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace texsim::img {
namespace {

constexpr int kBins = 8;

} // namespace

ColourHistogram::ColourHistogram(int channels) : channels_(channels) {
  TEXSIM_VERIFY(channels >= 1 && channels <= 4,
                "a colour histogram needs 1 to 4 channels, got " << channels);
  std::size_t bins = 1;
  for (int c = 0; c < channels; ++c)
    bins *= kBins;
  counts_.assign(bins, 0);
}

void ColourHistogram::add(std::span<const float> values) {
  const auto channels = static_cast<std::size_t>(channels_);
  TEXSIM_VERIFY(values.size() % channels == 0, "a colour histogram of "
                                                   << channels_ << " channels cannot count "
                                                   << values.size() << " values");
  for (std::size_t e = 0; e < values.size() / channels; ++e) {
    std::size_t bin = 0;
    for (std::size_t c = 0; c < channels; ++c) {
      const float value = values[e * channels + c];
      const int level =
          std::min(kBins - 1, static_cast<int>(std::clamp(value, 0.0f, 1.0f) * kBins));
      bin = bin * kBins + std::size_t(level);
    }
    ++counts_[bin];
  }
}

double histogram_distance(const ColourHistogram& a, const ColourHistogram& b) {
  const auto total = [](const ColourHistogram& h) {
    return std::accumulate(h.counts().begin(), h.counts().end(), std::int64_t{0});
  };
  const std::int64_t total_a = total(a), total_b = total(b);
  TEXSIM_VERIFY(a.channels() == b.channels() && total_a > 0 && total_b > 0,
                "histogram_distance needs two non-empty histograms of the same channels, got "
                    << a.channels() << " channels (" << total_a << " elements) and " << b.channels()
                    << " (" << total_b << ")");
  double sum = 0.0;
  for (std::size_t bin = 0; bin < a.counts().size(); ++bin)
    sum += std::abs(double(a.counts()[bin]) / double(total_a) -
                    double(b.counts()[bin]) / double(total_b));
  return 0.5 * sum;
}

double histogram_distance(std::span<const float> a, std::span<const float> b, int channels) {
  TEXSIM_VERIFY(channels >= 1 && channels <= 4 && !a.empty() && !b.empty() &&
                    a.size() % std::size_t(channels) == 0 && b.size() % std::size_t(channels) == 0,
                "histogram_distance needs 1 to 4 channels and whole, non-empty element lists, got "
                    << channels << " channels, " << a.size() << " and " << b.size() << " values");
  ColourHistogram histogram_a(channels), histogram_b(channels);
  histogram_a.add(a);
  histogram_b.add(b);
  return histogram_distance(histogram_a, histogram_b);
}

} // namespace texsim::img
