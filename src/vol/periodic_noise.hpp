#pragma once
/// Tileable Perlin-style gradient noise: random unit gradients on an integer lattice that repeats
/// every `period` cells, drawn from texsim::CounterRng keyed by the wrapped lattice point, so the
/// noise is deterministic per seed and periodic, and exemplars built from it tile.
#include <cstdint>
#include <vector>

namespace texsim::vol {

/// One octave of gradient noise on a lattice of period^3 cells.
class PeriodicGradientNoise {
public:
  /// `octave` selects an independent lattice for the same seed; period >= 1 cells.
  PeriodicGradientNoise(std::uint64_t seed, std::uint32_t octave, int period);

  /// Noise at lattice coordinates (x, y, z): smooth (quintic fade), 0 at lattice points, roughly
  /// in [-1, 1], and f(x + period, y, z) = f(x, y, z) for every axis.
  double operator()(double x, double y, double z) const;

  int period() const { return period_; }

private:
  double dot_gradient(int i, int j, int k, double dx, double dy, double dz) const;

  int period_;
  std::vector<double> gradients_; // 3 per lattice point, x fastest
};

/// Sums of octaves in tile coordinates: one unit of (u, v, w) is one period of every octave, so
/// both sums are periodic with period 1 along each axis.
class PeriodicFractalNoise {
public:
  /// Octave o has a lattice of base_period * 2^o cells per tile and weight 2^-o.
  PeriodicFractalNoise(std::uint64_t seed, int base_period, int octaves);

  /// Fractional Brownian motion: sum_o 2^-o noise_o(tile * base_period * 2^o), zero mean.
  double fbm(double u, double v, double w) const;
  /// Perlin turbulence: sum_o 2^-o |noise_o(...)|, non-negative.
  double turbulence(double u, double v, double w) const;

private:
  std::vector<PeriodicGradientNoise> octaves_;
};

} // namespace texsim::vol
