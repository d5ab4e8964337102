#pragma once
/// Colouring a scalar pattern for output: values mapped linearly from [lo, hi] onto a
/// piecewise-linear ramp of colour stops, e.g. Turk's dark spots on a tan background.
#include "core/config.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace texsim::pipelines::turk_rd {

/// A ramp stop: colour `rgb` (components in [0, 1]) at ramp parameter `at` (in [0, 1]).
struct ColorStop {
  double at;
  std::array<double, 3> rgb;
};

/// Turk's spots: tan background (low values) to dark brown spots (high values).
std::vector<ColorStop> tan_to_dark_stops();

class PatternColormap {
public:
  /// Config key read by from_config().
  static constexpr const char* kKey = "colors";

  /// At least two stops with strictly increasing `at` in [0, 1] and components in [0, 1]; throws
  /// Error otherwise.
  explicit PatternColormap(std::vector<ColorStop> stops);

  /// The ramp from `section`'s `colors:` key, a list of at least two [r, g, b] colours with
  /// components in [0, 1], placed at evenly spaced stops (the first at 0, the last at 1);
  /// `default_stops` when the key is absent. Throws InputError naming the key for bad input.
  static PatternColormap from_config(const ConfigSection& section,
                                     std::vector<ColorStop> default_stops);

  /// The ramp colour (components in [0, 1]) at parameter t: linear between neighbouring stops,
  /// the end colours outside [first.at, last.at]; NaN gives the first colour.
  std::array<double, 3> rgb(double t) const;

  /// 8-bit colour of value v, with [lo, hi] mapped linearly onto [0, 1] and clamped. When
  /// hi <= lo the map is a step: v <= lo gives the colour at 0, v > lo the colour at 1.
  std::array<std::uint8_t, 3> color(double v, double lo, double hi) const;

  /// color() of every value, interleaved r, g, b (3 * values.size() bytes). OpenMP.
  std::vector<std::uint8_t> colors(std::span<const double> values, double lo, double hi) const;

  const std::vector<ColorStop>& stops() const { return stops_; }

private:
  std::vector<ColorStop> stops_;
};

} // namespace texsim::pipelines::turk_rd
