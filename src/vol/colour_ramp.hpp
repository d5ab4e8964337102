#pragma once
/// Piecewise-linear colour ramps for procedural exemplars.
#include "img/rgb.hpp"

#include <algorithm>
#include <initializer_list>

namespace texsim::vol {

/// A ramp stop: colour at parameter t.
struct RampStop {
  float t;
  img::Rgb colour;
};

/// The colour at t, interpolated linearly between the stops (sorted by t); clamped to the end
/// colours outside [first.t, last.t].
inline img::Rgb colour_ramp(std::initializer_list<RampStop> stops, float t) {
  const RampStop* s = stops.begin();
  if (t <= s->t) {
    return s->colour;
  }
  for (; s + 1 != stops.end(); ++s) {
    if (t <= s[1].t) {
      return img::lerp(s->colour, s[1].colour, (t - s->t) / (s[1].t - s->t));
    }
  }
  return s->colour;
}

} // namespace texsim::vol
