#include "img/gaussian_pyramid.hpp"

namespace texsim::img {
namespace {

template <class T> const T& sample(const Image<T>& image, int x, int y, Border border) {
  return border == Border::periodic ? image.periodic(x, y) : image.clamped(x, y);
}

/// One pass of the kernel along x (dx = 1) or y (dy = 1).
template <class T>
Image<T> blur_1d(const Image<T>& image, int dx, int dy, int spacing, Border border) {
  Image<T> out(image.width(), image.height());
#pragma omp parallel for schedule(static)
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      T sum{};
      for (int t = -2; t <= 2; ++t) {
        sum += sample(image, x + t * spacing * dx, y + t * spacing * dy, border) *
               kBinomial5[static_cast<std::size_t>(t + 2)];
      }
      out.at(x, y) = sum;
    }
  }
  return out;
}

template <class T> Image<T> decimate(const Image<T>& image) {
  Image<T> out((image.width() + 1) / 2, (image.height() + 1) / 2);
  for (int y = 0; y < out.height(); ++y) {
    for (int x = 0; x < out.width(); ++x) {
      out.at(x, y) = image.at(2 * x, 2 * y);
    }
  }
  return out;
}

} // namespace

template <class T> Image<T> binomial_blur(const Image<T>& image, int spacing, Border border) {
  TEXSIM_VERIFY(spacing >= 1, "binomial blur spacing must be >= 1, got " << spacing);
  return blur_1d(blur_1d(image, 1, 0, spacing, border), 0, 1, spacing, border);
}

template <class T>
std::vector<Image<T>> gaussian_pyramid(const Image<T>& image, int levels, Border border) {
  TEXSIM_VERIFY(levels >= 1, "a pyramid needs at least one level, got " << levels);
  std::vector<Image<T>> pyramid{image};
  for (int l = 1; l < levels; ++l) {
    const Image<T>& fine = pyramid.back();
    TEXSIM_VERIFY(fine.width() > 1 || fine.height() > 1,
                  "pyramid level " << l - 1 << " is 1 x 1 and cannot be decimated");
    TEXSIM_VERIFY(border != Border::periodic || (fine.width() % 2 == 0 && fine.height() % 2 == 0),
                  "periodic pyramid level " << l - 1 << " is " << fine.width() << " x "
                                            << fine.height() << ", expected even sides");
    pyramid.push_back(decimate(binomial_blur(fine, 1, border)));
  }
  return pyramid;
}

template <class T>
std::vector<Image<T>> gaussian_stack(const Image<T>& image, int levels, Border border) {
  TEXSIM_VERIFY(levels >= 1, "a stack needs at least one level, got " << levels);
  std::vector<Image<T>> stack{image};
  for (int l = 1; l < levels; ++l) {
    stack.push_back(binomial_blur(stack.back(), 1 << (l - 1), border));
  }
  return stack;
}

template Image<float> binomial_blur(const Image<float>&, int, Border);
template Image<Rgb> binomial_blur(const Image<Rgb>&, int, Border);
template std::vector<Image<float>> gaussian_pyramid(const Image<float>&, int, Border);
template std::vector<Image<Rgb>> gaussian_pyramid(const Image<Rgb>&, int, Border);
template std::vector<Image<float>> gaussian_stack(const Image<float>&, int, Border);
template std::vector<Image<Rgb>> gaussian_stack(const Image<Rgb>&, int, Border);

} // namespace texsim::img
