#pragma once
/// The feature-aware erosion test of section 5.2: a patch texel at uv with interpolated weight w
/// is eroded iff sqrt(F_m + D) / max(sqrt(F_m + D)) - epsilon < 1 - w, D(u, v) = max(0, 1 -
/// |(0.5, 0.5) - (u, v)| / 0.5).
#include <Eigen/Core>

#include <array>
#include <vector>

namespace texsim::pipelines::fluid_lapped {

class ErosionMask {
public:
  /// `feature_map`: F_m in [0, 1] per exemplar texel, row-major, row 0 at the top (img::Image's
  /// convention), `width` x `height`; epsilon in ]0, 1[.
  ErosionMask(std::vector<float> feature_map, int width, int height, double epsilon);

  /// The exemplar texel (x, y) (row 0 at the top) whose cell holds uv: the exemplar spans
  /// [0, 1]^2 with v = 0 at the bottom row, and repeats outside. Colours and erosion both use it.
  std::array<int, 2> exemplar_texel(const Eigen::Vector2d& uv) const;

  /// True when the patch texel at uv, with weight w interpolated in its triangle, is eroded.
  /// F_m and D are taken at the centre of exemplar_texel(uv) (D from the unwrapped centre, so
  /// D = 0 outside the unit disk around (0.5, 0.5)).
  bool eroded(const Eigen::Vector2d& uv, double weight) const;

  /// max over the exemplar's texels of sqrt(F_m + D), the normaliser.
  double normaliser() const { return normaliser_; }

private:
  /// D at the centre of the texel cell holding uv, unwrapped.
  static double centre_falloff(const Eigen::Vector2d& centre);

  std::vector<float> feature_;
  int width_, height_;
  double epsilon_;
  double normaliser_ = 0;
  /// sqrt(F_m + D) / normaliser - epsilon per exemplar texel (row 0 at the top), the left side of
  /// the test: with D at the texel's centre for uv in [0, 1]^2, and with D = 0 for the repeats
  /// outside it (their unwrapped centres lie outside the disk). Computed once, as eroded() would.
  std::vector<double> shape_inside_, shape_outside_;
};

} // namespace texsim::pipelines::fluid_lapped
