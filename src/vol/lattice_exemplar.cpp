#include "core/rng.hpp"
#include "vol/procedural_exemplars.hpp"

#include <array>
#include <cmath>

namespace texsim::vol {
namespace {

constexpr std::uint32_t kLatticeBlobStream = 0x7606; // CounterRng stream of the cell's blobs
constexpr int kBlobs = 4;
constexpr double kBlobSigma = 0.15; ///< Gaussian width of a blob's weight, cell units

/// Offset a - b wrapped into [-0.5, 0.5): the shortest displacement on the unit torus.
double torus_delta(double a, double b) {
  const double d = a - b;
  return d - std::floor(d + 0.5);
}

/// The period^3 cell: every voxel blends the blob colours with Gaussian weights of its torus
/// distance to the blob centres, so the cell is smooth across its own faces.
RgbGrid lattice_cell(int period, std::uint64_t seed) {
  const CounterRng rng(seed, kLatticeBlobStream);
  std::array<std::array<double, 3>, kBlobs> centres{};
  std::array<img::Rgb, kBlobs> colours{};
  for (int b = 0; b < kBlobs; ++b) {
    const auto id = static_cast<std::uint64_t>(b);
    for (std::uint32_t a = 0; a < 3; ++a) {
      centres[static_cast<std::size_t>(b)][a] = rng.uniform(id, 0, a);
      colours[static_cast<std::size_t>(b)][static_cast<int>(a)] =
          static_cast<float>(rng.uniform(0.1, 0.9, id, 1, a));
    }
  }
  RgbGrid cell(Dims{period, period, period});
  for (int k = 0; k < period; ++k) {
    for (int j = 0; j < period; ++j) {
      for (int i = 0; i < period; ++i) {
        const std::array<double, 3> p{static_cast<double>(i) / period,
                                      static_cast<double>(j) / period,
                                      static_cast<double>(k) / period};
        std::array<double, 3> sum{};
        double total = 0.0;
        for (int b = 0; b < kBlobs; ++b) {
          double d2 = 0.0;
          for (std::size_t a = 0; a < 3; ++a) {
            const double d = torus_delta(p[a], centres[static_cast<std::size_t>(b)][a]);
            d2 += d * d;
          }
          const double weight = std::exp(-d2 / (2.0 * kBlobSigma * kBlobSigma));
          total += weight;
          for (int c = 0; c < 3; ++c) {
            sum[static_cast<std::size_t>(c)] += weight * colours[static_cast<std::size_t>(b)][c];
          }
        }
        cell.at(i, j, k) = {static_cast<float>(sum[0] / total), static_cast<float>(sum[1] / total),
                            static_cast<float>(sum[2] / total)};
      }
    }
  }
  return cell;
}

} // namespace

RgbGrid lattice_exemplar(int n, int period, std::uint64_t seed) {
  TEXSIM_VERIFY(period >= 1 && n >= period && n % period == 0,
                "lattice exemplar size must be a positive multiple of the period, got n = "
                    << n << ", period = " << period);
  const RgbGrid cell = lattice_cell(period, seed);
  RgbGrid grid(Dims{n, n, n});
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        grid.at(i, j, k) = cell.at(i % period, j % period, k % period);
      }
    }
  }
  return grid;
}

} // namespace texsim::vol
