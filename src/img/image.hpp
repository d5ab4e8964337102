#pragma once
/// Dense 2D images: row-major pixels, row 0 at the top, x to the right.
#include "core/error.hpp"
#include "img/rgb.hpp"

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

namespace texsim::img {

/// A width x height image of pixels of type T stored row by row (x fastest), row 0 at the top.
/// Colour values are nominally in [0, 1]; nothing clamps them.
template <class T> class Image {
public:
  using value_type = T;

  Image() = default;
  /// An image with every pixel set to `fill`; width, height > 0.
  Image(int width, int height, const T& fill = T{})
      : width_(width), height_(height),
        pixels_(static_cast<std::size_t>(checked(width, height)) * static_cast<std::size_t>(height),
                fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t size() const { return pixels_.size(); }

  /// Pixel (x, y), 0 <= x < width, 0 <= y < height (checked in debug builds only).
  T& at(int x, int y) { return pixels_[index(x, y)]; }
  const T& at(int x, int y) const { return pixels_[index(x, y)]; }

  /// Pixel (x mod width, y mod height) for any integers, negatives included: the image as a torus.
  const T& periodic(int x, int y) const {
    return pixels_[index(wrap(x, width_), wrap(y, height_))];
  }

  /// Pixel at (x, y) clamped into the image: the border pixels extend outwards.
  const T& clamped(int x, int y) const {
    return pixels_[index(std::clamp(x, 0, width_ - 1), std::clamp(y, 0, height_ - 1))];
  }

  std::span<T> data() { return pixels_; }
  std::span<const T> data() const { return pixels_; }

  friend bool operator==(const Image&, const Image&) = default;

private:
  static int checked(int width, int height) {
    TEXSIM_VERIFY(width > 0 && height > 0,
                  "image size must be positive, got " << width << " x " << height);
    return width;
  }
  static int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
  }
  std::size_t index(int x, int y) const {
    TEXSIM_ASSERT(x >= 0 && x < width_ && y >= 0 && y < height_,
                  "pixel (" << x << ", " << y << ") outside " << width_ << " x " << height_);
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(x);
  }

  int width_ = 0;
  int height_ = 0;
  std::vector<T> pixels_;
};

/// Colour image, channels in [0, 1].
using RgbImage = Image<Rgb>;
/// Single-channel image (luminance, masks, feature channels).
using GreyImage = Image<float>;

} // namespace texsim::img
