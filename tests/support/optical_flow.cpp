#include "support/optical_flow.hpp"

#include <algorithm>
#include <cmath>

namespace texsim::test {
namespace {

GreyPicture reduce(const GreyPicture& image) {
  GreyPicture half{std::max(1, image.width / 2), std::max(1, image.height / 2), {}};
  half.values.resize(std::size_t(half.width) * std::size_t(half.height));
  for (int y = 0; y < half.height; ++y)
    for (int x = 0; x < half.width; ++x) {
      const int x0 = std::min(2 * x, image.width - 1), x1 = std::min(2 * x + 1, image.width - 1);
      const int y0 = std::min(2 * y, image.height - 1), y1 = std::min(2 * y + 1, image.height - 1);
      half.values[std::size_t(y) * std::size_t(half.width) + std::size_t(x)] =
          0.25f * (image.at(x0, y0) + image.at(x1, y0) + image.at(x0, y1) + image.at(x1, y1));
    }
  return half;
}

/// Bilinear sample with clamping.
double sample(const GreyPicture& image, double x, double y) {
  x = std::clamp(x, 0.0, double(image.width - 1));
  y = std::clamp(y, 0.0, double(image.height - 1));
  const int x0 = std::min(int(x), image.width - 2 >= 0 ? image.width - 2 : 0);
  const int y0 = std::min(int(y), image.height - 2 >= 0 ? image.height - 2 : 0);
  const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
  const double fx = x - x0, fy = y - y0;
  return (1 - fy) * ((1 - fx) * image.at(x0, y0) + fx * image.at(x1, y0)) +
         fy * ((1 - fx) * image.at(x0, y1) + fx * image.at(x1, y1));
}

} // namespace

LucasKanade::LucasKanade(const GreyPicture& first, const GreyPicture& second, int levels,
                         int half_window)
    : half_window_(half_window) {
  first_.push_back(first);
  second_.push_back(second);
  for (int l = 1; l < levels; ++l) {
    first_.push_back(reduce(first_.back()));
    second_.push_back(reduce(second_.back()));
  }
}

FlowVector LucasKanade::at(int x, int y) const {
  double gx = 0, gy = 0; // guess carried down the pyramid
  double smallest_eigenvalue = 0;
  const int w = half_window_;
  for (int level = int(first_.size()) - 1; level >= 0; --level) {
    const auto& I = first_[std::size_t(level)];
    const auto& J = second_[std::size_t(level)];
    const double px = (x + 0.5) / double(1 << level) - 0.5,
                 py = (y + 0.5) / double(1 << level) - 0.5;
    double gxx = 0, gxy = 0, gyy = 0;
    for (int j = -w; j <= w; ++j)
      for (int i = -w; i <= w; ++i) {
        const double ix = 0.5 * (sample(I, px + i + 1, py + j) - sample(I, px + i - 1, py + j));
        const double iy = 0.5 * (sample(I, px + i, py + j + 1) - sample(I, px + i, py + j - 1));
        gxx += ix * ix;
        gxy += ix * iy;
        gyy += iy * iy;
      }
    const double det = gxx * gyy - gxy * gxy;
    const double trace = gxx + gyy;
    smallest_eigenvalue = 0.5 * (trace - std::sqrt(std::max(0.0, trace * trace - 4 * det)));
    double vx = 0, vy = 0;
    if (det > 1e-12) {
      for (int iteration = 0; iteration < 20; ++iteration) {
        double bx = 0, by = 0;
        for (int j = -w; j <= w; ++j)
          for (int i = -w; i <= w; ++i) {
            const double ix = 0.5 * (sample(I, px + i + 1, py + j) - sample(I, px + i - 1, py + j));
            const double iy = 0.5 * (sample(I, px + i, py + j + 1) - sample(I, px + i, py + j - 1));
            const double difference =
                sample(I, px + i, py + j) - sample(J, px + i + gx + vx, py + j + gy + vy);
            bx += difference * ix;
            by += difference * iy;
          }
        const double ex = (gyy * bx - gxy * by) / det, ey = (gxx * by - gxy * bx) / det;
        vx += ex;
        vy += ey;
        if (ex * ex + ey * ey < 1e-6)
          break;
      }
    }
    if (level > 0) {
      gx = 2 * (gx + vx);
      gy = 2 * (gy + vy);
    } else {
      gx += vx;
      gy += vy;
    }
  }
  const double window_pixels = double((2 * w + 1) * (2 * w + 1));
  return {gx, gy, smallest_eigenvalue / window_pixels > 1e-4};
}

FlowVector lucas_kanade(const GreyPicture& first, const GreyPicture& second, int x, int y,
                        int levels, int half_window) {
  return LucasKanade(first, second, levels, half_window).at(x, y);
}

} // namespace texsim::test
