#include "vol/gaussian_stack_3d.hpp"

#include "img/gaussian_pyramid.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace texsim::vol {
namespace {

constexpr int kTaps = static_cast<int>(img::kBinomial5.size());

/// One pass of the kernel along `axis` (0 = x, 1 = y, 2 = z).
ChannelGrid blur_along(const ChannelGrid& in, int axis, int spacing, bool periodic) {
  const Dims dims = in.dims();
  const std::array<int, 3> n{dims.nx, dims.ny, dims.nz};
  const std::array<std::size_t, 3> stride{1, static_cast<std::size_t>(dims.nx),
                                          static_cast<std::size_t>(dims.nx) *
                                              static_cast<std::size_t>(dims.ny)};
  const int length = n[static_cast<std::size_t>(axis)];
  const std::size_t step = stride[static_cast<std::size_t>(axis)];
  // tap_position[t * length + a]: where tap t of the voxel at position a along the axis reads.
  std::vector<std::size_t> tap_position(static_cast<std::size_t>(kTaps * length));
  for (int t = 0; t < kTaps; ++t) {
    for (int a = 0; a < length; ++a) {
      const int p = a + (t - kTaps / 2) * spacing;
      tap_position[static_cast<std::size_t>(t * length + a)] = static_cast<std::size_t>(
          periodic ? ChannelGrid::wrap(p, length) : ChannelGrid::clamp(p, length));
    }
  }
  const int channels = in.channels();
  ChannelGrid out(dims, channels);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < dims.nz; ++k) {
    for (int j = 0; j < dims.ny; ++j) {
      for (int i = 0; i < dims.nx; ++i) {
        const std::array<int, 3> position{i, j, k};
        const int a = position[static_cast<std::size_t>(axis)];
        const std::size_t voxel = in.index(i, j, k);
        const std::size_t line_start = voxel - static_cast<std::size_t>(a) * step;
        auto sum = out.voxel(voxel);
        for (int t = 0; t < kTaps; ++t) {
          const auto tap =
              in.voxel(line_start + tap_position[static_cast<std::size_t>(t * length + a)] * step);
          const float weight = img::kBinomial5[static_cast<std::size_t>(t)];
          for (int c = 0; c < channels; ++c) {
            sum[static_cast<std::size_t>(c)] += weight * tap[static_cast<std::size_t>(c)];
          }
        }
      }
    }
  }
  return out;
}

} // namespace

int coarsest_stack_level(Dims dims) {
  const int largest = std::max({dims.nx, dims.ny, dims.nz});
  int level = 0;
  while ((1 << level) < largest) {
    ++level;
  }
  return level;
}

ChannelGrid binomial_blur_3d(const ChannelGrid& grid, int spacing, bool periodic) {
  TEXSIM_VERIFY(spacing >= 1, "binomial blur spacing must be >= 1, got " << spacing);
  return blur_along(blur_along(blur_along(grid, 0, spacing, periodic), 1, spacing, periodic), 2,
                    spacing, periodic);
}

std::vector<ChannelGrid> gaussian_stack(const ChannelGrid& exemplar, bool periodic) {
  const int coarsest = coarsest_stack_level(exemplar.dims());
  std::vector<ChannelGrid> stack{exemplar};
  stack.reserve(static_cast<std::size_t>(coarsest) + 1);
  for (int s = 0; s < coarsest; ++s) {
    stack.push_back(binomial_blur_3d(stack.back(), 1 << s, periodic));
  }
  return stack;
}

} // namespace texsim::vol
