#include "core/float_distance_scan.hpp"

#include "core/rng.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

// Every kernel compiled for every instruction set this CPU runs, against exact double distances:
// a candidate within a bound is always handed to the callback (the scan's certificate), the
// distances handed over are within FloatDistanceBound's rounding of the exact ones, excluded
// lanes never hit, and lowered thresholds are re-read.
namespace texsim {
namespace {

/// Candidates in lane blocks, queries and their exact distances.
struct ScanProblem {
  int channels = 0;
  std::int64_t chunks = 0;
  std::vector<float> lane_blocks;
  std::vector<float> queries; ///< kScanQueries x channels

  ScanProblem(int channels_, std::int64_t chunks_, std::uint64_t seed)
      : channels(channels_), chunks(chunks_),
        lane_blocks(static_cast<std::size_t>(chunks * channels * kScanLanes)),
        queries(static_cast<std::size_t>(kScanQueries * channels)) {
    const CounterRng rng(seed, 0);
    for (std::size_t i = 0; i < lane_blocks.size(); ++i)
      lane_blocks[i] = static_cast<float>(rng.uniform(i, 0) * 2.0 - 1.0);
    for (std::size_t i = 0; i < queries.size(); ++i)
      queries[i] = static_cast<float>(rng.uniform(i, 1) * 2.0 - 1.0);
  }

  double exact(int query, std::int64_t candidate) const {
    const std::int64_t chunk = candidate / kScanLanes;
    const int lane = static_cast<int>(candidate % kScanLanes);
    double sum = 0.0;
    for (int c = 0; c < channels; ++c) {
      const double diff =
          static_cast<double>(
              lane_blocks[static_cast<std::size_t>((chunk * channels + c) * kScanLanes + lane)]) -
          static_cast<double>(queries[static_cast<std::size_t>(query * channels + c)]);
      sum += diff * diff;
    }
    return sum;
  }
};

/// What the callback saw: per query, the candidates below its threshold and their float
/// distances.
struct Hits {
  const float* thresholds = nullptr;
  int queries = kScanQueries;
  std::int64_t calls = 0;
  std::vector<std::set<std::int64_t>> below = std::vector<std::set<std::int64_t>>(kScanQueries);
  std::vector<std::vector<std::pair<std::int64_t, float>>> distances =
      std::vector<std::vector<std::pair<std::int64_t, float>>>(kScanQueries);

  static void record(void* context, std::int64_t chunk, const float* lanes) {
    auto& hits = *static_cast<Hits*>(context);
    ++hits.calls;
    bool any = false;
    for (int j = 0; j < hits.queries; ++j)
      for (int lane = 0; lane < kScanLanes; ++lane) {
        const float distance = lanes[j * kScanLanes + lane];
        const std::int64_t candidate = chunk * kScanLanes + lane;
        hits.distances[static_cast<std::size_t>(j)].emplace_back(candidate, distance);
        if (distance < hits.thresholds[j]) {
          hits.below[static_cast<std::size_t>(j)].insert(candidate);
          any = true;
        }
      }
    EXPECT_TRUE(any) << "chunk " << chunk << " handed over without a lane below a threshold";
  }
};

FloatDistanceScan scan_of(const ScanProblem& problem, const float* thresholds, Hits& hits) {
  FloatDistanceScan scan{};
  scan.lane_blocks = problem.lane_blocks.data();
  scan.chunk_begin = 0;
  scan.chunk_end = problem.chunks;
  scan.channels = problem.channels;
  scan.query_features = problem.queries.data();
  scan.thresholds = thresholds;
  scan.on_hit = Hits::record;
  scan.context = &hits;
  hits.thresholds = thresholds;
  return scan;
}

/// Per query, a bound that about `fraction` of the candidates fall within.
std::vector<double> bounds_of(const ScanProblem& problem, double fraction) {
  std::vector<double> bounds;
  for (int j = 0; j < kScanQueries; ++j) {
    std::vector<double> all;
    for (std::int64_t i = 0; i < problem.chunks * kScanLanes; ++i)
      all.push_back(problem.exact(j, i));
    std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(fraction * all.size()),
                     all.end());
    bounds.push_back(all[static_cast<std::size_t>(fraction * all.size())]);
  }
  return bounds;
}

class EveryIsa : public ::testing::TestWithParam<ScanIsa> {};

TEST_P(EveryIsa, BlockKernelHandsOverEveryCandidateWithinTheBoundAndExactDistances) {
  for (const int channels : {1, 3, 8, 13, 33}) {
    const ScanProblem problem(channels, 40, 7 + static_cast<std::uint64_t>(channels));
    const FloatDistanceBound rounding(channels);
    const auto bounds = bounds_of(problem, 0.004);
    float thresholds[kScanQueries];
    for (int j = 0; j < kScanQueries; ++j)
      thresholds[j] = rounding.threshold(bounds[static_cast<std::size_t>(j)], true);
    Hits hits;
    scan_float_distances(ScanKernel::kBlock, scan_of(problem, thresholds, hits), GetParam());
    for (int j = 0; j < kScanQueries; ++j) {
      const auto& below = hits.below[static_cast<std::size_t>(j)];
      for (std::int64_t i = 0; i < problem.chunks * kScanLanes; ++i) {
        if (problem.exact(j, i) <= bounds[static_cast<std::size_t>(j)]) {
          EXPECT_TRUE(below.count(i)) << "channels " << channels << " query " << j << " row " << i;
        }
      }
      for (const auto& [candidate, distance] : hits.distances[static_cast<std::size_t>(j)]) {
        const double exact = problem.exact(j, candidate);
        EXPECT_LE(std::abs(distance - exact), 2.0 * (channels + 3) * std::ldexp(exact, -24) + 1e-30)
            << "channels " << channels << " query " << j << " row " << candidate;
      }
    }
    // About 0.4 % of the rows are within each of the 8 bounds: about half the chunks are skipped.
    EXPECT_LT(hits.calls, problem.chunks);
  }
}

TEST_P(EveryIsa, MaskedKernelAddsPenaltiesAndInfinityExcludes) {
  const int channels = 8;
  const ScanProblem problem(channels, 12, 99);
  std::vector<std::vector<float>> penalties(kScanQueries);
  float thresholds[kScanQueries];
  for (int j = 0; j < kScanQueries; ++j) {
    thresholds[j] = kScanNoBound; // every lane that is not excluded hits
    auto& penalty = penalties[static_cast<std::size_t>(j)];
    for (std::int64_t i = 0; i < problem.chunks * kScanLanes; ++i)
      penalty.push_back((i + j) % 3 == 0 ? std::numeric_limits<float>::infinity()
                                         : static_cast<float>(i % 5));
  }
  Hits hits;
  FloatDistanceScan scan = scan_of(problem, thresholds, hits);
  for (int j = 0; j < kScanQueries; ++j)
    scan.penalties[j] = penalties[static_cast<std::size_t>(j)].data();
  scan_float_distances(ScanKernel::kMasked, scan, GetParam());
  EXPECT_EQ(hits.calls, problem.chunks);
  for (int j = 0; j < kScanQueries; ++j)
    for (const auto& [candidate, distance] : hits.distances[static_cast<std::size_t>(j)]) {
      if ((candidate + j) % 3 == 0) {
        EXPECT_FALSE(distance < thresholds[j]) << "excluded row " << candidate << " hit";
        continue;
      }
      const double expected = problem.exact(j, candidate) + static_cast<double>(candidate % 5);
      EXPECT_NEAR(distance, expected, 1e-5 * expected) << "query " << j << " row " << candidate;
    }
}

TEST_P(EveryIsa, SingleKernelScansSlotZeroOnly) {
  for (const int channels : {1, 5, 8, 16, 19}) {
    const ScanProblem problem(channels, 30, 3 + static_cast<std::uint64_t>(channels));
    const FloatDistanceBound rounding(channels);
    const double bound = bounds_of(problem, 0.1)[0];
    float thresholds[kScanQueries];
    std::fill(thresholds, thresholds + kScanQueries, kScanNoBound); // ignored but for slot 0
    thresholds[0] = rounding.threshold(bound, true);
    Hits hits;
    hits.queries = 1;
    scan_float_distances(ScanKernel::kSingle, scan_of(problem, thresholds, hits), GetParam());
    for (std::int64_t i = 0; i < problem.chunks * kScanLanes; ++i) {
      if (problem.exact(0, i) <= bound) {
        EXPECT_TRUE(hits.below[0].count(i)) << "channels " << channels << " row " << i;
      }
    }
    for (const auto& [candidate, distance] : hits.distances[0]) {
      const double exact = problem.exact(0, candidate);
      EXPECT_LE(std::abs(distance - exact), 2.0 * (channels + 3) * std::ldexp(exact, -24) + 1e-30);
    }
    EXPECT_LT(hits.calls, problem.chunks);
  }
}

TEST_P(EveryIsa, ThresholdsLoweredByTheCallbackAreReadForTheNextChunk) {
  const ScanProblem problem(8, 20, 5);
  float thresholds[kScanQueries];
  std::fill(thresholds, thresholds + kScanQueries, kScanNoBound);
  struct Stop {
    float* thresholds;
    std::int64_t calls = 0;
  } stop{thresholds};
  FloatDistanceScan scan{};
  scan.lane_blocks = problem.lane_blocks.data();
  scan.chunk_end = problem.chunks;
  scan.channels = problem.channels;
  scan.query_features = problem.queries.data();
  scan.thresholds = thresholds;
  scan.context = &stop;
  scan.on_hit = [](void* context, std::int64_t, const float*) {
    auto& s = *static_cast<Stop*>(context);
    ++s.calls;
    std::fill(s.thresholds, s.thresholds + kScanQueries, kScanNeverHits);
  };
  for (const ScanKernel kernel : {ScanKernel::kBlock, ScanKernel::kSingle}) {
    std::fill(thresholds, thresholds + kScanQueries, kScanNoBound);
    stop.calls = 0;
    scan_float_distances(kernel, scan, GetParam());
    EXPECT_EQ(stop.calls, 1);
  }
}

INSTANTIATE_TEST_SUITE_P(ScanKernels, EveryIsa, ::testing::ValuesIn(supported_scan_isas()),
                         [](const auto& info) { return std::string(scan_isa_name(info.param)); });

TEST(ScanIsa, EveryMachineRunsTheBaselineAndTheBestIsSupported) {
  const auto isas = supported_scan_isas();
  ASSERT_FALSE(isas.empty());
  EXPECT_EQ(isas.front(), ScanIsa::kSse2);
  EXPECT_EQ(isas.back(), best_scan_isa()); // TEXSIM_SCAN_ISA is not set under ctest
}

} // namespace
} // namespace texsim
