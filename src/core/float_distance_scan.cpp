#include "core/float_distance_scan.hpp"

#include <emmintrin.h>

#include <cmath>
#include <cstring>

namespace texsim {
namespace {

using Floats = float __attribute__((vector_size(kScanLanes * sizeof(float))));
using Bits = std::int32_t __attribute__((vector_size(kScanLanes * sizeof(float))));
using Words = std::uint64_t __attribute__((vector_size(kScanLanes * sizeof(float))));

/// Float squared distances of `Queries` queries to the 16 candidates of each chunk; `Masked`
/// adds the penalties. Hits are rare: the common path is subtract, multiply-add and a sign test.
template <bool Masked, int Queries>
[[gnu::always_inline]] inline void scan_chunks_body(const FloatDistanceScan& s) {
  const int d = s.channels;
  const float* q = s.query_features;
  for (std::int64_t chunk = s.chunk_begin; chunk < s.chunk_end; ++chunk) {
    const float* lanes = s.lane_blocks + chunk * d * kScanLanes;
    Floats x;
    std::memcpy(&x, lanes, sizeof x);
    Floats acc[Queries];
#pragma GCC unroll 16
    for (int j = 0; j < Queries; ++j) {
      const Floats diff = x - q[j * d];
      acc[j] = diff * diff;
    }
    for (int c = 1; c < d; ++c) {
      std::memcpy(&x, lanes + c * kScanLanes, sizeof x);
#pragma GCC unroll 16
      for (int j = 0; j < Queries; ++j) {
        const Floats diff = x - q[j * d + c];
        acc[j] += diff * diff;
      }
    }
    if constexpr (Masked) {
#pragma GCC unroll 16
      for (int j = 0; j < Queries; ++j) {
        Floats penalty;
        std::memcpy(&penalty, s.penalties[j] + (chunk - s.chunk_begin) * kScanLanes,
                    sizeof penalty);
        acc[j] += penalty;
      }
    }
    // acc - threshold is negative exactly where acc < threshold (both finite or acc = +inf);
    // or-ing the bit patterns keeps any sign bit. Generic vector code, no comparisons: GCC keeps
    // this vectorised in every target clone.
    Bits any = reinterpret_cast<Bits>(acc[0] - s.thresholds[0]);
#pragma GCC unroll 16
    for (int j = 1; j < Queries; ++j)
      any |= reinterpret_cast<Bits>(acc[j] - s.thresholds[j]);
    const Words words = reinterpret_cast<Words>(any);
    std::uint64_t sign = 0;
#pragma GCC unroll 8
    for (int w = 0; w < kScanLanes / 2; ++w)
      sign |= words[w];
    if (sign & 0x8000000080000000ull) {
      alignas(64) float distances[kScanQueries * kScanLanes];
      std::memcpy(distances, acc, sizeof acc);
      s.on_hit(s.context, chunk, distances);
    }
  }
}

using Half = float __attribute__((vector_size(kScanLanes / 2 * sizeof(float))));
using HalfBits = std::int32_t __attribute__((vector_size(kScanLanes / 2 * sizeof(float))));

/// One query: the block kernel's single accumulator per lane would be one long dependency chain
/// (and GCC keeps a lone 16-float vector on the stack under AVX2), so here each half chunk (8
/// lanes, one AVX2 register) sums four channel phases in separate registers: eight independent
/// chains. Float sums of non-negative terms in any order keep FloatDistanceBound's error bound.
[[gnu::always_inline]] inline void scan_single_body(const FloatDistanceScan& s) {
  constexpr int kPhases = 4;
  constexpr int kHalf = kScanLanes / 2;
  const int d = s.channels;
  const float* q = s.query_features;
  for (std::int64_t chunk = s.chunk_begin; chunk < s.chunk_end; ++chunk) {
    const float* lanes = s.lane_blocks + chunk * d * kScanLanes;
    Half acc[kPhases][2] = {};
    int c = 0;
    for (; c + kPhases <= d; c += kPhases)
#pragma GCC unroll 4
      for (int p = 0; p < kPhases; ++p)
#pragma GCC unroll 2
        for (int h = 0; h < 2; ++h) {
          Half x;
          std::memcpy(&x, lanes + (c + p) * kScanLanes + h * kHalf, sizeof x);
          const Half diff = x - q[c + p];
          acc[p][h] += diff * diff;
        }
    for (; c < d; ++c)
#pragma GCC unroll 2
      for (int h = 0; h < 2; ++h) {
        Half x;
        std::memcpy(&x, lanes + c * kScanLanes + h * kHalf, sizeof x);
        const Half diff = x - q[c];
        acc[0][h] += diff * diff;
      }
    Half sum[2];
#pragma GCC unroll 2
    for (int h = 0; h < 2; ++h)
      sum[h] = (acc[0][h] + acc[1][h]) + (acc[2][h] + acc[3][h]);
    // The block kernel's sign test: negative exactly where sum < threshold.
    const HalfBits any = reinterpret_cast<HalfBits>(sum[0] - s.thresholds[0]) |
                         reinterpret_cast<HalfBits>(sum[1] - s.thresholds[0]);
    bool hit = false;
#pragma GCC unroll 8
    for (int l = 0; l < kHalf; ++l)
      hit |= any[l] < 0;
    if (hit) {
      alignas(64) float distances[kScanQueries * kScanLanes];
      std::memcpy(distances, sum, sizeof sum);
      s.on_hit(s.context, chunk, distances);
    }
  }
}

} // namespace

__attribute__((target_clones("avx512f", "avx2", "default"))) void
scan_float_distances(const FloatDistanceScan& scan) {
  scan_chunks_body<false, kScanQueries>(scan);
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void
scan_float_distances_masked(const FloatDistanceScan& scan) {
  scan_chunks_body<true, kScanQueries>(scan);
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void
scan_float_distances_single(const FloatDistanceScan& scan) {
  scan_single_body(scan);
}

unsigned lanes_below(const float* lanes, float threshold) {
  // SSE2, part of x86-64.
  const __m128 limit = _mm_set1_ps(threshold);
  unsigned mask = 0;
  for (int group = 0; group < kScanLanes / 4; ++group)
    mask |=
        static_cast<unsigned>(_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(lanes + 4 * group), limit)))
        << (4 * group);
  return mask;
}

FloatDistanceBound::FloatDistanceBound(int channels)
    : channels_(channels),
      // Each difference rounds once, each square and sum at most twice, so |float - exact| <=
      // (d + 3) 2^-24 exact + the subnormal spacing per operation; doubled for margin.
      relative_error_(2.0 * (channels + 3) * std::ldexp(1.0, -24)) {}

float FloatDistanceBound::largest_safe_value() const {
  return static_cast<float>(std::sqrt(static_cast<double>(FLT_MAX) / (16.0 * channels_)));
}

float FloatDistanceBound::threshold(double bound, bool strict) const {
  const double subnormal_slack = (channels_ + 1) * std::ldexp(1.0, -149);
  if (bound == 0.0 && !strict)
    return 0.0f;
  const double limit = bound * (1.0 + relative_error_) + subnormal_slack;
  if (!(limit < static_cast<double>(kScanNoBound)))
    return kScanNoBound;
  float threshold = static_cast<float>(limit);
  if (static_cast<double>(threshold) <= limit)
    threshold = std::nextafter(threshold, kScanNoBound);
  return threshold;
}

} // namespace texsim
