#include "core/float_distance_scan.hpp"

#include "core/error.hpp"

#include <emmintrin.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

namespace texsim {
namespace {

/// `Width` floats: one register of the instruction set the kernel is compiled for (4 SSE2,
/// 8 AVX2, 16 AVX-512).
template <int Width> using Floats [[gnu::vector_size(Width * sizeof(float))]] = float;
template <int Width> using Bits [[gnu::vector_size(Width * sizeof(float))]] = std::int32_t;
template <int Width> using Words [[gnu::vector_size(Width * sizeof(float))]] = std::uint64_t;

/// True where some lane of `sign` has its sign bit set: the lanes or-ed as 64-bit words, so the
/// test stays a few vector instructions for every width.
template <int Width> [[gnu::always_inline]] inline bool any_sign_bit(const Bits<Width>& sign) {
  const Words<Width> words = reinterpret_cast<Words<Width>>(sign);
  std::uint64_t any = 0;
#pragma GCC unroll 8
  for (int w = 0; w < Width / 2; ++w)
    any |= words[w];
  return (any & 0x8000000080000000ull) != 0;
}

/// Float squared distances of `Queries` queries to the 16 candidates of each chunk; `Masked`
/// adds the penalties. The chunk is taken `Width` lanes at a time ("parts"), so the Queries
/// accumulators are one register each: 8 of the 16 registers AVX2 has (with two registers a
/// query, as a 16-float vector needs under AVX2, they were spilled to the stack on every
/// channel). Hits are rare: the common path is subtract, multiply-add and a sign test; a chunk
/// with a hit and more than one part has its parts computed again to hand over its distances.
template <bool Masked, int Queries, int Width>
[[gnu::always_inline]] inline void scan_chunks_body(const FloatDistanceScan& s) {
  using Vector = Floats<Width>;
  constexpr int kParts = kScanLanes / Width;
  const int d = s.channels;
  const float* q = s.query_features;
  const auto part_distances = [&](std::int64_t chunk, int part, Vector* acc) {
    const float* lanes = s.lane_blocks + chunk * d * kScanLanes + part * Width;
    Vector x;
    std::memcpy(&x, lanes, sizeof x);
#pragma GCC unroll 16
    for (int j = 0; j < Queries; ++j) {
      const Vector diff = x - q[j * d];
      acc[j] = diff * diff;
    }
    for (int c = 1; c < d; ++c) {
      std::memcpy(&x, lanes + c * kScanLanes, sizeof x);
#pragma GCC unroll 16
      for (int j = 0; j < Queries; ++j) {
        const Vector diff = x - q[j * d + c];
        acc[j] += diff * diff;
      }
    }
    if constexpr (Masked) {
#pragma GCC unroll 16
      for (int j = 0; j < Queries; ++j) {
        Vector penalty;
        std::memcpy(&penalty, s.penalties[j] + (chunk - s.chunk_begin) * kScanLanes + part * Width,
                    sizeof penalty);
        acc[j] += penalty;
      }
    }
  };
  alignas(64) float distances[kScanQueries * kScanLanes];
  const auto store = [&](int part, const Vector* acc) {
#pragma GCC unroll 16
    for (int j = 0; j < Queries; ++j)
      std::memcpy(distances + j * kScanLanes + part * Width, &acc[j], sizeof acc[j]);
  };
  for (std::int64_t chunk = s.chunk_begin; chunk < s.chunk_end; ++chunk) {
    Bits<Width> sign{};
    Vector acc[Queries];
#pragma GCC unroll 4
    for (int part = 0; part < kParts; ++part) {
      part_distances(chunk, part, acc);
      // acc - threshold is negative exactly where acc < threshold (both finite or acc = +inf);
      // or-ing the bit patterns keeps any sign bit. Generic vector code, no comparisons.
#pragma GCC unroll 16
      for (int j = 0; j < Queries; ++j)
        sign |= reinterpret_cast<Bits<Width>>(acc[j] - s.thresholds[j]);
    }
    if (!any_sign_bit<Width>(sign))
      continue;
    if constexpr (kParts == 1) {
      store(0, acc);
    } else {
      for (int part = 0; part < kParts; ++part) {
        part_distances(chunk, part, acc);
        store(part, acc);
      }
    }
    s.on_hit(s.context, chunk, distances);
  }
}

/// One query: the block kernel's single accumulator per lane would be one long dependency chain,
/// so the channels are summed in Width / 2 phases, each in its own registers: with the 16 / Width
/// registers a chunk takes, eight independent chains. Float sums of non-negative terms in any
/// order keep FloatDistanceBound's error bound.
template <int Width>
[[gnu::always_inline]] inline void scan_single_body(const FloatDistanceScan& s) {
  using Vector = Floats<Width>;
  constexpr int kPhases = Width / 2;
  constexpr int kParts = kScanLanes / Width;
  const int d = s.channels;
  const float* q = s.query_features;
  alignas(64) float distances[kScanQueries * kScanLanes];
  for (std::int64_t chunk = s.chunk_begin; chunk < s.chunk_end; ++chunk) {
    const float* lanes = s.lane_blocks + chunk * d * kScanLanes;
    Vector acc[kPhases][kParts] = {};
    int c = 0;
    for (; c + kPhases <= d; c += kPhases)
#pragma GCC unroll 8
      for (int p = 0; p < kPhases; ++p)
#pragma GCC unroll 4
        for (int h = 0; h < kParts; ++h) {
          Vector x;
          std::memcpy(&x, lanes + (c + p) * kScanLanes + h * Width, sizeof x);
          const Vector diff = x - q[c + p];
          acc[p][h] += diff * diff;
        }
    for (; c < d; ++c)
#pragma GCC unroll 4
      for (int h = 0; h < kParts; ++h) {
        Vector x;
        std::memcpy(&x, lanes + c * kScanLanes + h * Width, sizeof x);
        const Vector diff = x - q[c];
        acc[0][h] += diff * diff;
      }
    Bits<Width> sign{};
#pragma GCC unroll 4
    for (int h = 0; h < kParts; ++h) {
#pragma GCC unroll 8
      for (int p = 1; p < kPhases; ++p)
        acc[0][h] += acc[p][h];
      // The block kernel's sign test: negative exactly where the sum < threshold.
      sign |= reinterpret_cast<Bits<Width>>(acc[0][h] - s.thresholds[0]);
      std::memcpy(distances + h * Width, &acc[0][h], sizeof acc[0][h]);
    }
    if (any_sign_bit<Width>(sign))
      s.on_hit(s.context, chunk, distances);
  }
}

/// The kernels compiled for one instruction set, `Width` floats a register.
template <int Width>
[[gnu::always_inline]] inline void run_kernel(ScanKernel kernel, const FloatDistanceScan& scan) {
  switch (kernel) {
  case ScanKernel::kBlock:
    return scan_chunks_body<false, kScanQueries, Width>(scan);
  case ScanKernel::kMasked:
    return scan_chunks_body<true, kScanQueries, Width>(scan);
  case ScanKernel::kSingle:
    return scan_single_body<Width>(scan);
  }
}

[[gnu::target("avx512f,fma")]] void run_avx512(ScanKernel kernel, const FloatDistanceScan& scan) {
  run_kernel<16>(kernel, scan);
}

[[gnu::target("avx2,fma")]] void run_avx2(ScanKernel kernel, const FloatDistanceScan& scan) {
  run_kernel<8>(kernel, scan);
}

void run_sse2(ScanKernel kernel, const FloatDistanceScan& scan) {
  run_kernel<4>(kernel, scan);
}

ScanIsa widest_supported_isa() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma"))
    return ScanIsa::kAvx512;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    return ScanIsa::kAvx2;
  return ScanIsa::kSse2;
}

/// The widest set, or a narrower one named by TEXSIM_SCAN_ISA (to measure or test the kernels
/// another CPU would run).
ScanIsa detect_best_isa() {
  const ScanIsa widest = widest_supported_isa();
  const char* text = std::getenv("TEXSIM_SCAN_ISA");
  if (text == nullptr || *text == '\0')
    return widest;
  for (const ScanIsa isa : {ScanIsa::kSse2, ScanIsa::kAvx2, ScanIsa::kAvx512})
    if (std::strcmp(text, scan_isa_name(isa)) == 0) {
      if (isa > widest)
        TEXSIM_INPUT_ERROR("TEXSIM_SCAN_ISA=" << text << ": this CPU runs at most "
                                              << scan_isa_name(widest));
      return isa;
    }
  TEXSIM_INPUT_ERROR("TEXSIM_SCAN_ISA=" << text << ": expected sse2, avx2 or avx512");
}

} // namespace

ScanIsa best_scan_isa() {
  static const ScanIsa best = detect_best_isa();
  return best;
}

std::vector<ScanIsa> supported_scan_isas() {
  std::vector<ScanIsa> isas;
  for (const ScanIsa isa : {ScanIsa::kSse2, ScanIsa::kAvx2, ScanIsa::kAvx512})
    if (isa <= widest_supported_isa())
      isas.push_back(isa);
  return isas;
}

const char* scan_isa_name(ScanIsa isa) {
  switch (isa) {
  case ScanIsa::kSse2:
    return "sse2";
  case ScanIsa::kAvx2:
    return "avx2";
  case ScanIsa::kAvx512:
    return "avx512";
  }
  return "?";
}

void scan_float_distances(ScanKernel kernel, const FloatDistanceScan& scan, ScanIsa isa) {
  switch (isa) {
  case ScanIsa::kAvx512:
    return run_avx512(kernel, scan);
  case ScanIsa::kAvx2:
    return run_avx2(kernel, scan);
  case ScanIsa::kSse2:
    return run_sse2(kernel, scan);
  }
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
