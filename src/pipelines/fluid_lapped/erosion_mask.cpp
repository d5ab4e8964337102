#include "pipelines/fluid_lapped/erosion_mask.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace texsim::pipelines::fluid_lapped {

ErosionMask::ErosionMask(std::vector<float> feature_map, int width, int height, double epsilon)
    : feature_(std::move(feature_map)), width_(width), height_(height), epsilon_(epsilon) {
  TEXSIM_VERIFY(width > 0 && height > 0 && feature_.size() == std::size_t(width) * height,
                "erosion mask: " << feature_.size() << " feature values for " << width << " x "
                                 << height << " texels");
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Eigen::Vector2d centre((x + 0.5) / width_, 1.0 - (y + 0.5) / height_);
      const double f = feature_[std::size_t(y) * std::size_t(width_) + std::size_t(x)];
      normaliser_ = std::max(normaliser_, std::sqrt(f + centre_falloff(centre)));
    }
  shape_inside_.resize(feature_.size());
  shape_outside_.resize(feature_.size());
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const auto i = std::size_t(y) * std::size_t(width_) + std::size_t(x);
      const double f = feature_[i];
      // The centre as eroded() had it from uv: cell (x, row from the bottom) of the unit square.
      const Eigen::Vector2d centre((x + 0.5) / width_, (height_ - 1 - y + 0.5) / height_);
      shape_inside_[i] = std::sqrt(f + centre_falloff(centre)) / normaliser_ - epsilon_;
      shape_outside_[i] = std::sqrt(f + 0.0) / normaliser_ - epsilon_;
    }
}

std::array<int, 2> ErosionMask::exemplar_texel(const Eigen::Vector2d& uv) const {
  const auto wrap = [](long i, int n) { return int(((i % n) + n) % n); };
  const long column = long(std::floor(uv.x() * width_));
  const long row_from_bottom = long(std::floor(uv.y() * height_));
  return {wrap(column, width_), height_ - 1 - wrap(row_from_bottom, height_)};
}

double ErosionMask::centre_falloff(const Eigen::Vector2d& centre) {
  return std::max(0.0, 1.0 - (Eigen::Vector2d(0.5, 0.5) - centre).norm() / 0.5);
}

bool ErosionMask::eroded(const Eigen::Vector2d& uv, double weight) const {
  // The texel test runs for every atlas texel a patch triangle reaches: a table lookup, with the
  // modulo of exemplar_texel only for the repeats outside [0, 1]^2.
  const double column = std::floor(uv.x() * width_), row_from_bottom = std::floor(uv.y() * height_);
  if (column >= 0 && column < width_ && row_from_bottom >= 0 && row_from_bottom < height_) {
    const auto i =
        std::size_t(height_ - 1 - int(row_from_bottom)) * std::size_t(width_) + std::size_t(column);
    return shape_inside_[i] < 1.0 - weight;
  }
  const auto texel = exemplar_texel(uv);
  return shape_outside_[std::size_t(texel[1]) * std::size_t(width_) + std::size_t(texel[0])] <
         1.0 - weight;
}

} // namespace texsim::pipelines::fluid_lapped
