#pragma once
/// The colour type shared by images (img/) and volumes (vol/): three linear floats, nominally in
/// [0, 1], with the arithmetic that filters and pyramids need.
#include <type_traits>

namespace texsim::img {

/// An RGB colour; a plain aggregate of three floats (12 bytes, no padding) so arrays of it can be
/// handed to file formats as interleaved float triples.
struct Rgb {
  float r = 0.0f;
  float g = 0.0f;
  float b = 0.0f;

  /// The same value in all three channels (a grey level).
  static constexpr Rgb grey(float v) { return {v, v, v}; }

  constexpr float& operator[](int c) { return c == 0 ? r : (c == 1 ? g : b); }
  constexpr float operator[](int c) const { return c == 0 ? r : (c == 1 ? g : b); }

  constexpr Rgb& operator+=(const Rgb& o) {
    r += o.r;
    g += o.g;
    b += o.b;
    return *this;
  }
  constexpr Rgb& operator*=(float s) {
    r *= s;
    g *= s;
    b *= s;
    return *this;
  }
  friend constexpr Rgb operator+(Rgb a, const Rgb& b) { return a += b; }
  friend constexpr Rgb operator-(const Rgb& a, const Rgb& b) {
    return {a.r - b.r, a.g - b.g, a.b - b.b};
  }
  friend constexpr Rgb operator*(Rgb a, float s) { return a *= s; }
  friend constexpr Rgb operator*(float s, Rgb a) { return a *= s; }
  friend constexpr bool operator==(const Rgb&, const Rgb&) = default;
};

static_assert(sizeof(Rgb) == 3 * sizeof(float) && std::is_standard_layout_v<Rgb>);

/// Linear interpolation (1 - t) a + t b.
constexpr Rgb lerp(const Rgb& a, const Rgb& b, float t) {
  return a * (1.0f - t) + b * t;
}

} // namespace texsim::img
