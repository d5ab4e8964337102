#pragma once
/// Dense grids with a run-time number of float channels per voxel: colour (3), grey (1) and
/// appearance-space feature vectors (d) share one layout, so the solid-synthesis code is written
/// once for all of them.
#include "core/error.hpp"
#include "par/node_shared_array.hpp"
#include "vol/dense_grid.hpp"

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

namespace texsim::vol {

/// nx * ny * nz voxels of `channels` floats each, voxel-major (a voxel's channels are contiguous)
/// and x fastest, like DenseGrid. The values are the grid's own, or, for a read-only grid that
/// every rank reads whole (solid_synthesis' exemplar levels), held once per node
/// (par::NodeSharedArray).
class ChannelGrid {
public:
  ChannelGrid() = default;
  ChannelGrid(Dims dims, int channels, float fill = 0.0f)
      : dims_(dims), channels_(channels),
        values_(dims.count() * static_cast<std::size_t>(channels), fill) {
    check_shape();
  }
  /// A read-only grid on node-shared values: the non-const accessors refuse it.
  ChannelGrid(Dims dims, int channels, par::NodeSharedArray<float> shared)
      : dims_(dims), channels_(channels), shared_(std::move(shared)) {
    check_shape();
    TEXSIM_VERIFY(shared_.size() == dims.count() * static_cast<std::size_t>(channels),
                  "node-shared grid of " << shared_.size() << " values for " << dims.count()
                                         << " voxels of " << channels << " channels");
  }

  /// Whether the values are held once per node (read-only).
  bool node_shared() const { return shared_.data() != nullptr; }

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
    TEXSIM_ASSERT(!node_shared(), "a node-shared channel grid is read-only");
    return {values_.data() + voxel * static_cast<std::size_t>(channels_),
            static_cast<std::size_t>(channels_)};
  }
  std::span<const float> voxel(std::size_t voxel) const {
    return {data().data() + voxel * static_cast<std::size_t>(channels_),
            static_cast<std::size_t>(channels_)};
  }

  std::span<float> data() {
    TEXSIM_VERIFY(!node_shared(), "a node-shared channel grid is read-only");
    return values_;
  }
  std::span<const float> data() const {
    return node_shared() ? shared_.values() : std::span<const float>(values_);
  }

  /// Same shape and the same values, wherever they are held.
  friend bool operator==(const ChannelGrid& a, const ChannelGrid& b) {
    return a.dims_ == b.dims_ && a.channels_ == b.channels_ &&
           std::ranges::equal(a.data(), b.data());
  }

  static int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
  }
  static int clamp(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

private:
  void check_shape() const {
    TEXSIM_VERIFY(dims_.nx > 0 && dims_.ny > 0 && dims_.nz > 0 && channels_ > 0,
                  "channel grid needs positive dims and channels, got "
                      << dims_.nx << " x " << dims_.ny << " x " << dims_.nz << " x " << channels_);
  }

  Dims dims_;
  int channels_ = 0;
  std::vector<float> values_;          ///< empty when node-shared
  par::NodeSharedArray<float> shared_; ///< set when node-shared
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
