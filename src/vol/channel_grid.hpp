#pragma once
/// Dense grids with a run-time number of float channels per voxel: colour (3), grey (1) and
/// appearance-space feature vectors (d) share one layout, so the solid-synthesis code is written
/// once for all of them.
#include "core/error.hpp"
#include "vol/dense_grid.hpp"

#include <cstddef>
#include <span>
#include <vector>

namespace texsim::vol {

/// nx * ny * nz voxels of `channels` floats each, voxel-major (a voxel's channels are contiguous)
/// and x fastest, like DenseGrid.
class ChannelGrid {
public:
  ChannelGrid() = default;
  ChannelGrid(Dims dims, int channels, float fill = 0.0f)
      : dims_(dims), channels_(channels),
        values_(dims.count() * static_cast<std::size_t>(channels), fill) {
    TEXSIM_VERIFY(dims.nx > 0 && dims.ny > 0 && dims.nz > 0 && channels > 0,
                  "channel grid needs positive dims and channels, got "
                      << dims.nx << " x " << dims.ny << " x " << dims.nz << " x " << channels);
  }

  Dims dims() const { return dims_; }
  int channels() const { return channels_; }
  std::size_t voxel_count() const { return dims_.count(); }

  /// Storage index of voxel (i, j, k) inside the grid.
  std::size_t index(int i, int j, int k) const {
    TEXSIM_ASSERT(i >= 0 && i < dims_.nx && j >= 0 && j < dims_.ny && k >= 0 && k < dims_.nz,
                  "voxel (" << i << ", " << j << ", " << k << ") outside the grid");
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims_.nx) *
               (static_cast<std::size_t>(j) +
                static_cast<std::size_t>(dims_.ny) * static_cast<std::size_t>(k));
  }
  /// Index of voxel (i mod nx, j mod ny, k mod nz), negatives included: the grid as a 3-torus.
  std::size_t periodic_index(int i, int j, int k) const {
    return index(wrap(i, dims_.nx), wrap(j, dims_.ny), wrap(k, dims_.nz));
  }
  /// Index of voxel (i, j, k) clamped into the grid.
  std::size_t clamped_index(int i, int j, int k) const {
    return index(clamp(i, dims_.nx), clamp(j, dims_.ny), clamp(k, dims_.nz));
  }

  /// The channels of the voxel with storage index `voxel`.
  std::span<float> voxel(std::size_t voxel) {
    return {values_.data() + voxel * static_cast<std::size_t>(channels_),
            static_cast<std::size_t>(channels_)};
  }
  std::span<const float> voxel(std::size_t voxel) const {
    return {values_.data() + voxel * static_cast<std::size_t>(channels_),
            static_cast<std::size_t>(channels_)};
  }

  std::span<float> data() { return values_; }
  std::span<const float> data() const { return values_; }

  friend bool operator==(const ChannelGrid&, const ChannelGrid&) = default;

  static int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
  }
  static int clamp(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

private:
  Dims dims_;
  int channels_ = 0;
  std::vector<float> values_;
};

/// A colour grid as 3 channels, or a scalar grid as 1.
inline ChannelGrid to_channels(const RgbGrid& grid) {
  ChannelGrid out(grid.dims(), 3);
  const auto in = grid.data();
  for (std::size_t v = 0; v < in.size(); ++v) {
    auto c = out.voxel(v);
    c[0] = in[v].r;
    c[1] = in[v].g;
    c[2] = in[v].b;
  }
  return out;
}
inline ChannelGrid to_channels(const ScalarGrid& grid) {
  ChannelGrid out(grid.dims(), 1);
  std::copy(grid.data().begin(), grid.data().end(), out.data().begin());
  return out;
}

/// A 3-channel grid as colours, or a 1-channel grid as grey colours.
inline RgbGrid to_rgb(const ChannelGrid& grid) {
  TEXSIM_VERIFY(grid.channels() == 1 || grid.channels() == 3,
                "to_rgb needs 1 or 3 channels, got " << grid.channels());
  RgbGrid out(grid.dims());
  auto colours = out.data();
  for (std::size_t v = 0; v < colours.size(); ++v) {
    const auto c = grid.voxel(v);
    colours[v] = grid.channels() == 3 ? img::Rgb{c[0], c[1], c[2]} : img::Rgb{c[0], c[0], c[0]};
  }
  return out;
}

} // namespace texsim::vol
