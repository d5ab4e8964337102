#pragma once
/// Samples a function of tile coordinates on an n^3 grid; the building block of the procedural
/// exemplars.
#include "core/error.hpp"
#include "vol/dense_grid.hpp"

namespace texsim::vol {

/// An n^3 RgbGrid with voxel (i, j, k) = colour_at(i / n, j / n, k / n); colour_at must be safe to
/// call concurrently (OpenMP over k). Spacing 1, origin 0.
template <class ColourAt> RgbGrid sample_tile(int n, const ColourAt& colour_at) {
  TEXSIM_VERIFY(n >= 1, "exemplar size must be positive, got " << n);
  RgbGrid grid(Dims{n, n, n});
  const double inv = 1.0 / n;
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        grid.at(i, j, k) = colour_at(i * inv, j * inv, k * inv);
      }
    }
  }
  return grid;
}

} // namespace texsim::vol
