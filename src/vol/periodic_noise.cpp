#include "vol/periodic_noise.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"

#include <cmath>

namespace texsim::vol {
namespace {

constexpr std::uint32_t kGradientStream = 0x7601; // CounterRng stream of the noise lattices

double fade(double t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

int wrap(int i, int n) {
  const int m = i % n;
  return m < 0 ? m + n : m;
}

} // namespace

PeriodicGradientNoise::PeriodicGradientNoise(std::uint64_t seed, std::uint32_t octave, int period)
    : period_(period) {
  TEXSIM_VERIFY(period >= 1 && period <= 128, "noise period must be in [1, 128], got " << period);
  const CounterRng rng(seed, kGradientStream);
  const std::size_t points = static_cast<std::size_t>(period) * period * period;
  gradients_.resize(3 * points);
  for (std::size_t p = 0; p < points; ++p) {
    double g[3];
    double norm = 0.0;
    for (std::uint32_t c = 0; c < 3; ++c) {
      g[c] = rng.normal(p, octave, c);
      norm += g[c] * g[c];
    }
    norm = std::sqrt(norm);
    for (std::size_t c = 0; c < 3; ++c) {
      gradients_[3 * p + c] = norm > 0.0 ? g[c] / norm : 0.0;
    }
  }
}

double PeriodicGradientNoise::dot_gradient(int i, int j, int k, double dx, double dy,
                                           double dz) const {
  const std::size_t p =
      static_cast<std::size_t>(wrap(i, period_)) +
      static_cast<std::size_t>(period_) *
          (static_cast<std::size_t>(wrap(j, period_)) +
           static_cast<std::size_t>(period_) * static_cast<std::size_t>(wrap(k, period_)));
  return gradients_[3 * p] * dx + gradients_[3 * p + 1] * dy + gradients_[3 * p + 2] * dz;
}

double PeriodicGradientNoise::operator()(double x, double y, double z) const {
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const int i = static_cast<int>(fx), j = static_cast<int>(fy), k = static_cast<int>(fz);
  const double dx = x - fx, dy = y - fy, dz = z - fz;
  const double sx = fade(dx), sy = fade(dy), sz = fade(dz);
  double along_z[2];
  for (int c = 0; c < 2; ++c) {
    double along_y[2];
    for (int b = 0; b < 2; ++b) {
      const double v0 = dot_gradient(i, j + b, k + c, dx, dy - b, dz - c);
      const double v1 = dot_gradient(i + 1, j + b, k + c, dx - 1.0, dy - b, dz - c);
      along_y[b] = v0 + sx * (v1 - v0);
    }
    along_z[c] = along_y[0] + sy * (along_y[1] - along_y[0]);
  }
  // The largest value of 3D gradient noise with unit gradients is sqrt(3)/2; scale to about [-1,
  // 1].
  return (along_z[0] + sz * (along_z[1] - along_z[0])) * (2.0 / std::sqrt(3.0));
}

PeriodicFractalNoise::PeriodicFractalNoise(std::uint64_t seed, int base_period, int octaves) {
  TEXSIM_VERIFY(octaves >= 1 && octaves <= 10, "octaves must be in [1, 10], got " << octaves);
  for (int o = 0; o < octaves; ++o) {
    octaves_.emplace_back(seed, static_cast<std::uint32_t>(o), base_period << o);
  }
}

double PeriodicFractalNoise::fbm(double u, double v, double w) const {
  double sum = 0.0, weight = 1.0;
  for (const auto& noise : octaves_) {
    const double p = noise.period();
    sum += weight * noise(u * p, v * p, w * p);
    weight *= 0.5;
  }
  return sum;
}

double PeriodicFractalNoise::turbulence(double u, double v, double w) const {
  double sum = 0.0, weight = 1.0;
  for (const auto& noise : octaves_) {
    const double p = noise.period();
    sum += weight * std::abs(noise(u * p, v * p, w * p));
    weight *= 0.5;
  }
  return sum;
}

} // namespace texsim::vol
