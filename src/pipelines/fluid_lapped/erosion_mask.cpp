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

Eigen::Vector2d ErosionMask::texel_centre(const Eigen::Vector2d& uv) const {
  return {(std::floor(uv.x() * width_) + 0.5) / width_,
          (std::floor(uv.y() * height_) + 0.5) / height_};
}

bool ErosionMask::eroded(const Eigen::Vector2d& uv, double weight) const {
  const auto texel = exemplar_texel(uv);
  const double f = feature_[std::size_t(texel[1]) * std::size_t(width_) + std::size_t(texel[0])];
  const double shape = std::sqrt(f + centre_falloff(texel_centre(uv))) / normaliser_;
  return shape - epsilon_ < 1.0 - weight;
}

} // namespace texsim::pipelines::fluid_lapped
