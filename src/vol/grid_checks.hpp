#pragma once
/// Checks every volume reader applies to what a file declares and holds, before the grid is used:
/// a size that fits in memory (computed without overflow) and finite voxel values.
#include "vol/dense_grid.hpp"

#include <cmath>
#include <cstdint>
#include <filesystem>

namespace texsim::vol {

/// Throws InputError naming the file when `dims` x `bytes_per_voxel` cannot be allocated: a
/// dimension is not positive or above 2^31 - 1, the byte count overflows, or it exceeds the
/// memory of the node (core/memory_budget). Serial.
void require_grid_fits(const std::filesystem::path& path, std::int64_t nx, std::int64_t ny,
                       std::int64_t nz, std::uint64_t bytes_per_voxel);

/// Throws InputError naming the file and the first voxel holding a NaN or an infinity.
void refuse_non_finite_voxel(const std::filesystem::path& path, Dims dims, std::size_t index);

/// Checks every voxel of `grid` is finite (all channels of a colour). Serial.
template <class T>
void require_finite_voxels(const std::filesystem::path& path, const DenseGrid<T>& grid) {
  const auto values = grid.data();
  for (std::size_t n = 0; n < values.size(); ++n) {
    bool finite = true;
    if constexpr (std::is_same_v<T, float>)
      finite = std::isfinite(values[n]);
    else
      for (int c = 0; c < 3; ++c)
        finite = finite && std::isfinite(values[n][c]);
    if (!finite)
      refuse_non_finite_voxel(path, grid.dims(), n);
  }
}

/// require_finite_voxels() on whichever grid `grid` holds; returns it.
inline AnyGrid with_finite_voxels(const std::filesystem::path& path, AnyGrid grid) {
  std::visit([&](const auto& g) { require_finite_voxels(path, g); }, grid);
  return grid;
}

} // namespace texsim::vol
