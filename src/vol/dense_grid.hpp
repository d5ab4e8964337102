#pragma once
/// Dense voxel grids: nx * ny * nz values stored x fastest, with a voxel spacing and an origin in
/// world units. Depends on img/ only for the shared colour type img::Rgb.
#include "core/error.hpp"
#include "img/rgb.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <span>
#include <type_traits>
#include <variant>
#include <vector>

namespace texsim::vol {

/// Grid size in voxels along x, y, z.
struct Dims {
  int nx = 0;
  int ny = 0;
  int nz = 0;
  std::size_t count() const {
    return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) *
           static_cast<std::size_t>(nz);
  }
  friend bool operator==(const Dims&, const Dims&) = default;
};

/// A dense grid of voxel values of type T. Voxel (i, j, k) sits at world position
/// origin + (i, j, k) * spacing (componentwise), like VTK image data points and OpenVDB voxel
/// centres; storage index i + nx * (j + ny * k).
template <class T> class DenseGrid {
public:
  using value_type = T;

  DenseGrid() = default;
  /// A grid with every voxel set to `fill`; all dims > 0. Spacing 1, origin 0.
  DenseGrid(Dims dims, const T& fill = T{}) : dims_(checked(dims)), values_(dims.count(), fill) {}

  Dims dims() const { return dims_; }
  std::size_t size() const { return values_.size(); }

  /// Voxel edge lengths along x, y, z, world units.
  const std::array<double, 3>& spacing() const { return spacing_; }
  void set_spacing(const std::array<double, 3>& spacing) { spacing_ = spacing; }
  /// World position of voxel (0, 0, 0).
  const std::array<double, 3>& origin() const { return origin_; }
  void set_origin(const std::array<double, 3>& origin) { origin_ = origin; }

  /// Voxel (i, j, k) inside the grid (checked in debug builds only).
  T& at(int i, int j, int k) { return values_[index(i, j, k)]; }
  const T& at(int i, int j, int k) const { return values_[index(i, j, k)]; }

  /// Voxel (i mod nx, j mod ny, k mod nz) for any integers, negatives included: the grid as a
  /// 3-torus (tileable exemplars, toroidal neighbourhoods).
  const T& periodic(int i, int j, int k) const {
    return values_[index(wrap(i, dims_.nx), wrap(j, dims_.ny), wrap(k, dims_.nz))];
  }

  /// Voxel (i, j, k) clamped into the grid: boundary voxels extend outwards.
  const T& clamped(int i, int j, int k) const {
    return values_[index(std::clamp(i, 0, dims_.nx - 1), std::clamp(j, 0, dims_.ny - 1),
                         std::clamp(k, 0, dims_.nz - 1))];
  }

  /// All voxels, x fastest.
  std::span<T> data() { return values_; }
  std::span<const T> data() const { return values_; }

  /// Same dims, spacing and origin, and equal values voxel by voxel.
  friend bool operator==(const DenseGrid&, const DenseGrid&) = default;

private:
  static Dims checked(Dims dims) {
    TEXSIM_VERIFY(dims.nx > 0 && dims.ny > 0 && dims.nz > 0, "grid dims must be positive, got "
                                                                 << dims.nx << " x " << dims.ny
                                                                 << " x " << dims.nz);
    return dims;
  }
  static int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
  }
  std::size_t index(int i, int j, int k) const {
    TEXSIM_ASSERT(i >= 0 && i < dims_.nx && j >= 0 && j < dims_.ny && k >= 0 && k < dims_.nz,
                  "voxel (" << i << ", " << j << ", " << k << ") outside " << dims_.nx << " x "
                            << dims_.ny << " x " << dims_.nz);
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims_.nx) *
               (static_cast<std::size_t>(j) +
                static_cast<std::size_t>(dims_.ny) * static_cast<std::size_t>(k));
  }

  Dims dims_;
  std::array<double, 3> spacing_{1.0, 1.0, 1.0};
  std::array<double, 3> origin_{0.0, 0.0, 0.0};
  std::vector<T> values_;
};

/// One value per voxel (densities, level sets, grey exemplars).
using ScalarGrid = DenseGrid<float>;
/// A colour per voxel (solid texture exemplars and results), channels nominally in [0, 1].
using RgbGrid = DenseGrid<img::Rgb>;
/// What a file reader found: a scalar or a colour grid.
using AnyGrid = std::variant<ScalarGrid, RgbGrid>;

/// Float components per voxel value as file formats store them: 1 for float, 3 for img::Rgb.
template <class T> inline constexpr int voxel_components = std::is_same_v<T, img::Rgb> ? 3 : 1;

} // namespace texsim::vol
