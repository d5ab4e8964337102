#include "core/rng.hpp"
#include "vol/periodic_noise.hpp"
#include "vol/procedural_exemplars.hpp"
#include "vol/tile_sampling.hpp"

#include <algorithm>
#include <cmath>

namespace texsim::vol {
namespace {

constexpr std::uint32_t kBrickTintStream = 0x7604; // CounterRng stream of per-brick tints

int floor_mod(int i, int n) {
  return ((i % n) + n) % n;
}

} // namespace

RgbGrid brick_exemplar(int n, std::uint64_t seed, const BrickParams& p) {
  TEXSIM_VERIFY(p.bricks_x >= 1 && p.rows_y >= 2 && p.layers_z >= 2 && p.rows_y % 2 == 0 &&
                    p.layers_z % 2 == 0,
                "brick bond needs bricks_x >= 1 and even rows_y, layers_z >= 2 to tile, got "
                    << p.bricks_x << ", " << p.rows_y << ", " << p.layers_z);
  const CounterRng tint(seed, kBrickTintStream);
  const PeriodicFractalNoise grain(seed, 8, 3);
  const double size[3] = {1.0 / p.bricks_x, 1.0 / p.rows_y, 1.0 / p.layers_z};
  const double half_joint = 0.5 * p.mortar;
  return sample_tile(n, [&](double u, double v, double w) {
    // The bond is offset by a quarter brick along x and half a brick along y and z so the tile
    // faces cut through bricks rather than along joints.
    const double y = v * p.rows_y + 0.5;
    const double z = w * p.layers_z + 0.5;
    const int row = static_cast<int>(std::floor(y));
    const int layer = static_cast<int>(std::floor(z));
    // Running bond: rows and layers alternate by half a brick along x.
    const double x = u * p.bricks_x + 0.25 - ((row + layer) % 2 == 0 ? 0.0 : 0.5);
    const int column = static_cast<int>(std::floor(x));
    const double local[3] = {x - column, y - row, z - layer};
    double joint_distance = 1.0; // distance to the nearest brick face, tile units
    for (int a = 0; a < 3; ++a) {
      joint_distance = std::min(joint_distance, std::min(local[a], 1.0 - local[a]) * size[a]);
    }
    const auto texture = static_cast<float>(0.08 * grain.fbm(u, v, w));
    if (joint_distance < half_joint) {
      return p.mortar_colour * (1.0f + texture);
    }
    const std::uint64_t brick_id = static_cast<std::uint64_t>(
        floor_mod(column, p.bricks_x) +
        p.bricks_x * (floor_mod(row, p.rows_y) + p.rows_y * floor_mod(layer, p.layers_z)));
    const auto shade = static_cast<float>(tint.uniform(0.8, 1.2, brick_id, 0));
    return p.brick * (shade + texture);
  });
}

} // namespace texsim::vol
