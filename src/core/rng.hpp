#pragma once
/// Counter-based random numbers (Philox4x32-10, Salmon et al., SC'11): a draw is a pure function of
/// (seed, stream, global entity id, step, draw index), so results never depend on how entities are
/// split across ranks or threads, nor on the order in which they are visited.
#include <array>
#include <cmath>
#include <cstdint>

namespace texsim {

/// Usage: CounterRng rng(seed, streams::kNoise); double u = rng.uniform(vertex_gid, step);
/// Streams separate independent uses of one seed (noise, initial state, jitter ...); stream < 65536
/// and at most 131072 draws per (id, step).
class CounterRng {
public:
  CounterRng(std::uint64_t seed, std::uint32_t stream) : seed_(seed), stream_(stream) {}

  /// Four independent 32-bit words for (id, step, block). Thread-safe, no state.
  std::array<std::uint32_t, 4> bits(std::uint64_t id, std::uint32_t step,
                                    std::uint32_t block = 0) const {
    return philox4x32_10(
        {(stream_ << 16) | (block & 0xffffu), static_cast<std::uint32_t>(id),
         static_cast<std::uint32_t>(id >> 32), step},
        {static_cast<std::uint32_t>(seed_), static_cast<std::uint32_t>(seed_ >> 32)});
  }

  /// The Philox4x32 bijection with 10 rounds, as specified by Salmon et al. (Random123).
  static std::array<std::uint32_t, 4> philox4x32_10(std::array<std::uint32_t, 4> counter,
                                                    std::array<std::uint32_t, 2> key) {
    for (int round = 0; round < 10; ++round) {
      counter = philox_round(counter, key);
      key[0] += 0x9E3779B9u;
      key[1] += 0xBB67AE85u;
    }
    return counter;
  }

  /// Uniform double in [0, 1) with 53 random bits; `draw` picks the k-th number for the same
  /// (id, step).
  double uniform(std::uint64_t id, std::uint32_t step, std::uint32_t draw = 0) const {
    const auto w = bits(id, step, draw / 2);
    const std::uint64_t hi = draw % 2 == 0 ? w[0] : w[2];
    const std::uint64_t lo = draw % 2 == 0 ? w[1] : w[3];
    const std::uint64_t mantissa = ((hi << 32) | lo) >> 11;
    return static_cast<double>(mantissa) * 0x1.0p-53;
  }

  /// Uniform in [lo, hi).
  double uniform(double lo, double hi, std::uint64_t id, std::uint32_t step,
                 std::uint32_t draw = 0) const {
    return lo + (hi - lo) * uniform(id, step, draw);
  }

  /// Standard normal by Box-Muller from draws 2*draw and 2*draw+1.
  double normal(std::uint64_t id, std::uint32_t step, std::uint32_t draw = 0) const {
    const double u1 = 1.0 - uniform(id, step, 2 * draw); // in (0, 1]
    const double u2 = uniform(id, step, 2 * draw + 1);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

  std::uint64_t seed() const { return seed_; }
  std::uint32_t stream() const { return stream_; }

private:
  static std::array<std::uint32_t, 4> philox_round(const std::array<std::uint32_t, 4>& c,
                                                   const std::array<std::uint32_t, 2>& k) {
    const std::uint64_t p0 = std::uint64_t{0xD2511F53u} * c[0];
    const std::uint64_t p1 = std::uint64_t{0xCD9E8D57u} * c[2];
    return {static_cast<std::uint32_t>(p1 >> 32) ^ c[1] ^ k[0], static_cast<std::uint32_t>(p1),
            static_cast<std::uint32_t>(p0 >> 32) ^ c[3] ^ k[1], static_cast<std::uint32_t>(p0)};
  }

  std::uint64_t seed_;
  std::uint32_t stream_;
};

} // namespace texsim
