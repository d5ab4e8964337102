#pragma once
/// The per-vertex random substrate beta of Bajaj, Zhang, Xu (Figs. 3-5: "beta = 12.0 +/- 0.1"): a
/// value uniform in [mean - spread, mean + spread) drawn from the counter-based generator keyed by
/// the vertex id, so every vertex gets the same value on any partition and in any visiting order.
#include "core/rng.hpp"

#include <cstdint>

namespace texsim::rd {

/// CounterRng streams of the reaction models (one seed, independent uses).
inline constexpr std::uint32_t kSubstrateStream = 0x5244;       ///< beta of the built-in models
inline constexpr std::uint32_t kExpressionNoiseStream = 0x5245; ///< `noise` of expression models

class RandomSubstrate {
public:
  RandomSubstrate(std::uint64_t seed, double mean, double spread)
      : rng_(seed, kSubstrateStream), mean_(mean), spread_(spread) {}

  /// beta at the vertex with this id (input-mesh numbering). Thread-safe.
  double at(std::int64_t vertex_id) const {
    return rng_.uniform(mean_ - spread_, mean_ + spread_, static_cast<std::uint64_t>(vertex_id), 0);
  }

  double mean() const { return mean_; }
  double spread() const { return spread_; }

private:
  CounterRng rng_;
  double mean_;
  double spread_;
};

} // namespace texsim::rd
