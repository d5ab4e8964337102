#include "vol/gaussian_stack_3d.hpp"

#include "img/gaussian_pyramid.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace texsim::vol {
namespace {

constexpr int kTaps = static_cast<int>(img::kBinomial5.size());

/// Where tap t of position a along an axis of `length` voxels reads: tap_position[t * length + a].
std::vector<int> tap_positions(int length, int spacing, bool periodic) {
  std::vector<int> tap_position(static_cast<std::size_t>(kTaps * length));
  for (int t = 0; t < kTaps; ++t) {
    for (int a = 0; a < length; ++a) {
      const int p = a + (t - kTaps / 2) * spacing;
      tap_position[static_cast<std::size_t>(t * length + a)] =
          periodic ? ChannelGrid::wrap(p, length) : ChannelGrid::clamp(p, length);
    }
  }
  return tap_position;
}

/// out[v] = sum over taps t of w_t * in[v's tap t], with the taps' voxel indices from `tap_voxel`;
/// `out` holds zeros on entry. The sum runs over t in order, the same arithmetic for every pass.
template <class TapVoxel>
void accumulate_taps(const float* in, float* out, int channels, TapVoxel tap_voxel) {
  for (int t = 0; t < kTaps; ++t) {
    const float* tap = in + tap_voxel(t) * static_cast<std::size_t>(channels);
    const float weight = img::kBinomial5[static_cast<std::size_t>(t)];
    for (int c = 0; c < channels; ++c) {
      out[c] += weight * tap[c];
    }
  }
}

/// Plane z of `grid` blurred along x and then y, into `out` (nx * ny voxels, zeros on entry).
void blur_plane_xy(const ChannelGrid& grid, int z, const std::vector<int>& x_taps,
                   const std::vector<int>& y_taps, std::span<float> out) {
  const Dims dims = grid.dims();
  const int channels = grid.channels();
  const auto plane_voxels = static_cast<std::size_t>(dims.nx) * static_cast<std::size_t>(dims.ny);
  const float* in = grid.data().data() +
                    plane_voxels * static_cast<std::size_t>(z) * static_cast<std::size_t>(channels);
  std::vector<float> along_x(plane_voxels * static_cast<std::size_t>(channels));
  const auto row = [&](int j) { return static_cast<std::size_t>(j) * std::size_t(dims.nx); };
  for (int j = 0; j < dims.ny; ++j) {
    for (int i = 0; i < dims.nx; ++i) {
      accumulate_taps(
          in, along_x.data() + (row(j) + std::size_t(i)) * std::size_t(channels), channels,
          [&](int t) { return row(j) + std::size_t(x_taps[std::size_t(t * dims.nx + i)]); });
    }
  }
  for (int j = 0; j < dims.ny; ++j) {
    for (int i = 0; i < dims.nx; ++i) {
      accumulate_taps(
          along_x.data(), out.data() + (row(j) + std::size_t(i)) * std::size_t(channels), channels,
          [&](int t) { return row(y_taps[std::size_t(t * dims.ny + j)]) + std::size_t(i); });
    }
  }
}

} // namespace

void binomial_blur_3d_planes(const ChannelGrid& grid, int spacing, bool periodic, int z_begin,
                             int z_end, std::span<float> out) {
  TEXSIM_VERIFY(spacing >= 1, "binomial blur spacing must be >= 1, got " << spacing);
  const Dims dims = grid.dims();
  const int channels = grid.channels();
  const auto plane_values = static_cast<std::size_t>(dims.nx) * static_cast<std::size_t>(dims.ny) *
                            static_cast<std::size_t>(channels);
  TEXSIM_VERIFY(0 <= z_begin && z_begin <= z_end && z_end <= dims.nz &&
                    out.size() == plane_values * static_cast<std::size_t>(z_end - z_begin),
                "binomial blur of planes [" << z_begin << ", " << z_end << ") of a grid of "
                                            << dims.nz << " planes into " << out.size()
                                            << " values");
  const std::vector<int> x_taps = tap_positions(dims.nx, spacing, periodic);
  const std::vector<int> y_taps = tap_positions(dims.ny, spacing, periodic);
  const std::vector<int> z_taps = tap_positions(dims.nz, spacing, periodic);
  // Only the planes the z taps of [z_begin, z_end) read are blurred along x and y.
  std::vector<int> slot_of_plane(static_cast<std::size_t>(dims.nz), -1);
  std::vector<int> planes;
  for (int t = 0; t < kTaps; ++t) {
    for (int z = z_begin; z < z_end; ++z) {
      const int source = z_taps[static_cast<std::size_t>(t * dims.nz + z)];
      if (slot_of_plane[static_cast<std::size_t>(source)] < 0) {
        slot_of_plane[static_cast<std::size_t>(source)] = static_cast<int>(planes.size());
        planes.push_back(source);
      }
    }
  }
  std::vector<float> blurred_xy(plane_values * planes.size());
  const auto slot = [&](std::size_t p) {
    return std::span(blurred_xy).subspan(p * plane_values, plane_values);
  };
#pragma omp parallel for schedule(static)
  for (std::size_t p = 0; p < planes.size(); ++p) {
    blur_plane_xy(grid, planes[p], x_taps, y_taps, slot(p));
  }
  std::fill(out.begin(), out.end(), 0.0f);
  const auto plane_voxels = plane_values / static_cast<std::size_t>(channels);
#pragma omp parallel for schedule(static)
  for (int z = z_begin; z < z_end; ++z) {
    float* out_plane = out.data() + plane_values * static_cast<std::size_t>(z - z_begin);
    for (std::size_t v = 0; v < plane_voxels; ++v) {
      accumulate_taps(blurred_xy.data(), out_plane + v * static_cast<std::size_t>(channels),
                      channels, [&](int t) {
                        const int source = z_taps[static_cast<std::size_t>(t * dims.nz + z)];
                        return static_cast<std::size_t>(
                                   slot_of_plane[static_cast<std::size_t>(source)]) *
                                   plane_voxels +
                               v;
                      });
    }
  }
}

int coarsest_stack_level(Dims dims) {
  const int largest = std::max({dims.nx, dims.ny, dims.nz});
  int level = 0;
  while ((1 << level) < largest) {
    ++level;
  }
  return level;
}

ChannelGrid binomial_blur_3d(const ChannelGrid& grid, int spacing, bool periodic) {
  ChannelGrid out(grid.dims(), grid.channels());
  binomial_blur_3d_planes(grid, spacing, periodic, 0, grid.dims().nz, out.data());
  return out;
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
