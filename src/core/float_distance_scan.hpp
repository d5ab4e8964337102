#pragma once
/// The certified float scan shared by the exact nearest-neighbour searches (solid_synthesis'
/// similarity sets, surface_synthesis' exhaustive search): float squared distances of a block of
/// kScanQueries queries to candidates stored 16 to a chunk, compared against one float threshold
/// per query. A chunk where some query has a lane below its threshold is handed to a callback,
/// which computes exact (double) distances and may lower the thresholds. FloatDistanceBound turns
/// a bound on the exact distance into a threshold that the float distance of every candidate
/// within the bound stays below, so a candidate the scan skips is provably farther.
///
/// Layout ("lane blocks"): chunk i holds candidates 16 i .. 16 i + 15, channel-major: channel c
/// of lane l at [c * kScanLanes + l]. Padding lanes hold +inf and never hit.
#include <cfloat>
#include <cstdint>
#include <vector>

namespace texsim {

inline constexpr int kScanLanes = 16;  ///< candidates per chunk (one AVX-512 register of floats)
inline constexpr int kScanQueries = 8; ///< queries sharing each loaded chunk (register blocking)
inline constexpr float kScanNoBound = FLT_MAX;    ///< threshold without a bound: every lane hits
inline constexpr float kScanNeverHits = -FLT_MAX; ///< threshold of an unused query slot

/// Everything a scan of a run of chunks reads. `on_hit` gets the chunk's float distances
/// (kScanQueries x kScanLanes, query-major) and may lower `thresholds`, which are re-read.
struct FloatDistanceScan {
  const float* lane_blocks = nullptr;
  std::int64_t chunk_begin = 0;
  std::int64_t chunk_end = 0;
  int channels = 0;
  const float* query_features = nullptr; ///< kScanQueries x channels
  const float* thresholds = nullptr;     ///< kScanQueries
  /// Masked scans only: per query, kScanLanes x (chunk_end - chunk_begin) additive penalties
  /// (+inf excludes a lane).
  const float* penalties[kScanQueries] = {};
  void (*on_hit)(void* context, std::int64_t chunk, const float* distances) = nullptr;
  void* context = nullptr;
};

/// Instruction sets the kernels are compiled for; each kernel keeps its accumulators in
/// registers of that set's width (4, 8 or 16 floats).
enum class ScanIsa { kSse2, kAvx2, kAvx512 };
/// The widest set this CPU runs (AVX2 and AVX-512 with FMA), detected once; TEXSIM_SCAN_ISA=sse2,
/// avx2 or avx512 picks a narrower one (InputError if unknown or wider than the CPU runs).
ScanIsa best_scan_isa();
/// The sets this CPU runs, narrowest first (TEXSIM_SCAN_ISA aside): tests run each kernel.
std::vector<ScanIsa> supported_scan_isas();
const char* scan_isa_name(ScanIsa isa);

enum class ScanKernel {
  kBlock,  ///< kScanQueries queries
  kMasked, ///< the same with the penalties added to each distance
  kSingle, ///< query slot 0 only (the others are ignored and get no distances): a lone query
           ///< costs an eighth of a full block's arithmetic
};

/// Scans [chunk_begin, chunk_end) with `kernel` compiled for `isa` (which this CPU must run).
void scan_float_distances(ScanKernel kernel, const FloatDistanceScan& scan,
                          ScanIsa isa = best_scan_isa());

/// Bit i set where lanes[i] < threshold, for the kScanLanes lanes of a chunk.
unsigned lanes_below(const float* lanes, float threshold);

/// Rounding bounds of float squared distances over `channels` channels.
class FloatDistanceBound {
public:
  explicit FloatDistanceBound(int channels);

  /// Largest |value| for which channels * (2 max)^2 stays below FLT_MAX / 4: float distances
  /// never overflow and stay below kScanNoBound.
  float largest_safe_value() const;

  /// A float threshold such that a candidate whose float distance (computed by the scan from the
  /// same float values) is >= the threshold has exact distance > bound (>= bound if `strict` is
  /// false and bound = 0: the margin makes every other case strict). kScanNoBound if unbounded.
  float threshold(double bound, bool strict) const;

private:
  int channels_;
  double relative_error_;
};

} // namespace texsim
