#include "pipelines/turk_rd/pattern_colormap.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

namespace texsim::pipelines::turk_rd {
namespace {

/// The `colors:` list as read from YAML; a type of this file only, so the config converter below
/// cannot collide with one defined elsewhere.
struct ColorList {
  std::vector<std::array<double, 3>> rgb;
};

bool unit_interval(double x) {
  return x >= 0.0 && x <= 1.0;
}

} // namespace
} // namespace texsim::pipelines::turk_rd

namespace texsim::detail {
using texsim::pipelines::turk_rd::ColorList;

template <> std::optional<ColorList> convert<ColorList>(const YAML::Node& node) {
  if (!node.IsSequence())
    return std::nullopt;
  ColorList list;
  for (const auto& item : node) {
    const auto rgb = convert<Vec3Array>(item);
    if (!rgb)
      return std::nullopt;
    list.rgb.push_back(*rgb);
  }
  if (list.rgb.size() < 2)
    return std::nullopt;
  return list;
}

template <> std::string type_name<ColorList>() {
  return "a list of at least 2 [r, g, b] colours";
}
} // namespace texsim::detail

namespace texsim::pipelines::turk_rd {

std::vector<ColorStop> tan_to_dark_stops() {
  return {{0.0, {0.93, 0.78, 0.52}}, {1.0, {0.12, 0.08, 0.05}}};
}

PatternColormap::PatternColormap(std::vector<ColorStop> stops) : stops_(std::move(stops)) {
  TEXSIM_VERIFY(stops_.size() >= 2,
                "PatternColormap: needs at least 2 stops, got " << stops_.size());
  for (std::size_t i = 0; i < stops_.size(); ++i) {
    const ColorStop& s = stops_[i];
    TEXSIM_VERIFY(unit_interval(s.at),
                  "PatternColormap: stop " << i << " at " << s.at << " is outside [0, 1]");
    TEXSIM_VERIFY(i == 0 || stops_[i - 1].at < s.at,
                  "PatternColormap: stop positions must increase, stop " << i << " at " << s.at);
    for (const double c : s.rgb)
      TEXSIM_VERIFY(unit_interval(c),
                    "PatternColormap: stop " << i << " has component " << c << " outside [0, 1]");
  }
}

PatternColormap PatternColormap::from_config(const ConfigSection& section,
                                             std::vector<ColorStop> default_stops) {
  if (!section.has(kKey))
    return PatternColormap(std::move(default_stops));
  const Constraint<ColorList> in_unit_cube = [](const ColorList& list) {
    for (std::size_t i = 0; i < list.rgb.size(); ++i) {
      if (!std::all_of(list.rgb[i].begin(), list.rgb[i].end(), unit_interval)) {
        std::ostringstream out;
        out << "colour components in [0, 1] (colour " << i << " is [" << list.rgb[i][0] << ", "
            << list.rgb[i][1] << ", " << list.rgb[i][2] << "])";
        return out.str();
      }
    }
    return std::string();
  };
  const ColorList list = section.require<ColorList>(kKey, in_unit_cube);
  std::vector<ColorStop> stops(list.rgb.size());
  const double last = double(stops.size() - 1);
  for (std::size_t i = 0; i < stops.size(); ++i)
    stops[i] = {double(i) / last, list.rgb[i]};
  return PatternColormap(std::move(stops));
}

std::array<double, 3> PatternColormap::rgb(double t) const {
  if (!(t > stops_.front().at))
    return stops_.front().rgb;
  if (t >= stops_.back().at)
    return stops_.back().rgb;
  // First stop strictly above t; t lies in [below.at, above.at).
  const auto above = std::upper_bound(stops_.begin(), stops_.end(), t,
                                      [](double x, const ColorStop& s) { return x < s.at; });
  const ColorStop& lower = *(above - 1);
  const double f = (t - lower.at) / (above->at - lower.at);
  std::array<double, 3> out;
  for (int c = 0; c < 3; ++c)
    out[c] = lower.rgb[c] + f * (above->rgb[c] - lower.rgb[c]);
  return out;
}

std::array<std::uint8_t, 3> PatternColormap::color(double v, double lo, double hi) const {
  double t = 0.0;
  if (hi > lo)
    t = std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
  else
    t = v > lo ? 1.0 : 0.0;
  if (std::isnan(t))
    t = 0.0;
  const std::array<double, 3> c = rgb(t);
  std::array<std::uint8_t, 3> out;
  for (int k = 0; k < 3; ++k)
    out[k] = static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(c[k], 0.0, 1.0)));
  return out;
}

std::vector<std::uint8_t> PatternColormap::colors(std::span<const double> values, double lo,
                                                  double hi) const {
  std::vector<std::uint8_t> out(3 * values.size());
  const auto n = static_cast<std::int64_t>(values.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    const auto c = color(values[i], lo, hi);
    std::copy(c.begin(), c.end(), out.begin() + 3 * i);
  }
  return out;
}

} // namespace texsim::pipelines::turk_rd
