#pragma once
/// Trilinear interpolation of a colour (or 3-vector) grid at continuous voxel coordinates, the
/// grid clamped at its borders: velocity grids sampled in world space (fluid_lapped) and vector
/// fields stretched over the unit cube (solid_synthesis) both map their points to voxel
/// coordinates and call this.
#include "img/rgb.hpp"
#include "vol/dense_grid.hpp"

#include <array>

namespace texsim::vol {

/// The value at voxel coordinates `at` (voxel (i, j, k) sits at (i, j, k); between voxels the
/// eight around are blended, in double), each coordinate clamped to [0, n - 1].
std::array<double, 3> trilinear(const RgbGrid& grid, const std::array<double, 3>& at);

/// Voxel coordinates of world point `world` in `grid` (origin + index x spacing, as in .vti).
std::array<double, 3> voxel_coordinates(const RgbGrid& grid, const std::array<double, 3>& world);

} // namespace texsim::vol
