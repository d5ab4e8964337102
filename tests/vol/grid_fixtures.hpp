#pragma once
// Grids with every voxel distinct (and zeros, which sparse formats store as background), shared
// by the vol file-format tests.
#include "core/rng.hpp"
#include "support/input_error.hpp"
#include "vol/dense_grid.hpp"

#include <string>

namespace texsim::vol::test {

/// 5 x 7 x 3 random floats (every 4th voxel exactly 0) with non-trivial spacing and origin.
inline ScalarGrid odd_scalar_grid(std::uint64_t seed) {
  const CounterRng rng(seed, 9);
  ScalarGrid grid(Dims{5, 7, 3});
  for (std::size_t n = 0; n < grid.size(); ++n) {
    grid.data()[n] = n % 4 == 0 ? 0.0f : static_cast<float>(rng.uniform(-3.0, 7.0, n, 0));
  }
  grid.set_spacing({0.5, 0.25, 1.75});
  grid.set_origin({-1.5, 2.0, 0.125});
  return grid;
}

/// 5 x 7 x 3 random colours (every 5th voxel black) with non-trivial spacing and origin.
inline RgbGrid odd_rgb_grid(std::uint64_t seed) {
  const CounterRng rng(seed, 10);
  RgbGrid grid(Dims{5, 7, 3});
  for (std::size_t n = 0; n < grid.size(); ++n) {
    for (int c = 0; c < 3; ++c) {
      grid.data()[n][c] =
          n % 5 == 0 ? 0.0f : static_cast<float>(rng.uniform(n, 0, static_cast<std::uint32_t>(c)));
    }
  }
  grid.set_spacing({0.1, 0.2, 0.3});
  grid.set_origin({10.0, -20.0, 30.5});
  return grid;
}

/// Shared by all layers' tests (support/input_error.hpp); the vol tests call it through here.
using ::texsim::test::input_error_message;

} // namespace texsim::vol::test
