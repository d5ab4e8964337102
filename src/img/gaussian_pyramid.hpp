#pragma once
/// Gaussian pyramids and Gaussian stacks of images with the 5-tap binomial kernel
/// [1 4 6 4 1] / 16 (Burt & Adelson 1983; stacks as in Lefebvre & Hoppe 2005).
#include "img/image.hpp"

#include <array>
#include <vector>

namespace texsim::img {

/// How filters read outside the image.
enum class Border {
  periodic, ///< the image is a torus (tileable textures, exemplars)
  clamped,  ///< border pixels extend outwards
};

/// The binomial weights [1 4 6 4 1] / 16 for offsets -2..2. Their even and odd taps each sum to
/// 1/2, so blurring then keeping every other sample preserves the mean of a periodic signal.
inline constexpr std::array<float, 5> kBinomial5 = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16,
                                                    1.0f / 16};

/// Separable binomial blur whose taps are `spacing` pixels apart (spacing 1: the plain kernel;
/// spacing 2^l: the "a trous" kernel of stack level l + 1).
template <class T> Image<T> binomial_blur(const Image<T>& image, int spacing, Border border);

/// levels images: [0] is the input, [l + 1] is [l] blurred then decimated by 2 (even pixels kept),
/// size ceil(n / 2) per side. Periodic borders need every level but the last to have even sides.
/// Throws Error if a level to be decimated is 1 x 1 or, with periodic borders, has an odd side.
template <class T>
std::vector<Image<T>> gaussian_pyramid(const Image<T>& image, int levels, Border border);

/// levels images of the input's size: [0] is the input, [l + 1] is [l] blurred with taps 2^l
/// apart. With periodic borders, sampling level l every 2^l pixels gives pyramid level l.
template <class T>
std::vector<Image<T>> gaussian_stack(const Image<T>& image, int levels, Border border);

} // namespace texsim::img
