#include "core/rng.hpp"
#include "vol/procedural_exemplars.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace texsim::vol {
namespace {

constexpr std::uint32_t kPlacementStream = 0x7602; // CounterRng stream of candidate centres
constexpr std::uint32_t kTintStream = 0x7603;      // CounterRng stream of per-particle tints

/// Offset a - b wrapped into [-0.5, 0.5): the shortest displacement on the unit torus.
double torus_delta(double a, double b) {
  const double d = a - b;
  return d - std::floor(d + 0.5);
}

struct Sphere {
  std::array<double, 3> centre;
  img::Rgb colour;
};

std::vector<Sphere> place_spheres(std::uint64_t seed, const ParticleParams& p) {
  const double sphere_volume = 4.0 / 3.0 * std::numbers::pi * p.radius * p.radius * p.radius;
  const auto target = static_cast<std::size_t>(std::ceil(p.target_coverage / sphere_volume));
  const double min_distance = 2.0 * p.radius + p.min_gap;
  const CounterRng placement(seed, kPlacementStream);
  const CounterRng tint(seed, kTintStream);
  std::vector<Sphere> spheres;
  for (int attempt = 0; attempt < p.max_attempts && spheres.size() < target; ++attempt) {
    const auto id = static_cast<std::uint64_t>(attempt);
    const std::array<double, 3> c{placement.uniform(id, 0, 0), placement.uniform(id, 0, 1),
                                  placement.uniform(id, 0, 2)};
    bool free = true;
    for (const Sphere& s : spheres) {
      const double dx = torus_delta(c[0], s.centre[0]), dy = torus_delta(c[1], s.centre[1]),
                   dz = torus_delta(c[2], s.centre[2]);
      if (dx * dx + dy * dy + dz * dz < min_distance * min_distance) {
        free = false;
        break;
      }
    }
    if (free) {
      const auto shade = static_cast<float>(tint.uniform(0.85, 1.15, id, 0));
      spheres.push_back({c, p.particle * shade});
    }
  }
  return spheres;
}

} // namespace

RgbGrid particle_exemplar(int n, std::uint64_t seed, const ParticleParams& params) {
  TEXSIM_VERIFY(n >= 1, "exemplar size must be positive, got " << n);
  TEXSIM_VERIFY(params.radius > 0.0 && params.radius < 0.25,
                "particle radius must be in (0, 0.25) tile units, got " << params.radius);
  RgbGrid grid(Dims{n, n, n}, params.background);
  const double inv = 1.0 / n;
  // Spheres do not overlap, so each voxel is painted by at most one: visit each sphere's
  // bounding box of voxels, wrapped around the torus.
  for (const Sphere& s : place_spheres(seed, params)) {
    std::array<int, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      lo[a] = static_cast<int>(std::floor((s.centre[a] - params.radius) * n));
      hi[a] = static_cast<int>(std::ceil((s.centre[a] + params.radius) * n));
    }
    for (int k = lo[2]; k <= hi[2]; ++k) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const int wi = ((i % n) + n) % n, wj = ((j % n) + n) % n, wk = ((k % n) + n) % n;
          const double dx = torus_delta(wi * inv, s.centre[0]),
                       dy = torus_delta(wj * inv, s.centre[1]),
                       dz = torus_delta(wk * inv, s.centre[2]);
          if (dx * dx + dy * dy + dz * dz < params.radius * params.radius) {
            grid.at(wi, wj, wk) = s.colour;
          }
        }
      }
    }
  }
  return grid;
}

} // namespace texsim::vol
