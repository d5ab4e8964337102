#include "pipelines/surface_synthesis/exhaustive_search.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <omp.h>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr std::size_t kTileBytes = 128 * 1024; ///< lane blocks scanned per pass over the queries

} // namespace

/// One query of a batch: its float copy, rounding radius, threshold and best row so far.
struct ExhaustiveSearch::QueryState {
  const double* query = nullptr;
  std::vector<float> floats;
  double rounding = 0.0; ///< |q - float(q)|, rounded up
  float threshold = kScanNoBound;
  std::int64_t best = -1;
  double best_distance = 0.0;
};

ExhaustiveSearch::ExhaustiveSearch(NeighbourhoodTable table)
    : NeighbourhoodSearch(std::move(table)), float_bound_(dimension()) {
  const int d = dimension();
  safe_value_ = float_bound_.largest_safe_value();
  for (const float v : this->table().values)
    TEXSIM_VERIFY(std::abs(v) <= safe_value_,
                  "neighbourhood search: value " << v << " exceeds " << safe_value_);
  // Relative rounding of a double distance (d differences, squares and sums) and of the bound's
  // own arithmetic, with margin.
  kappa_ = (d + 8) * std::ldexp(1.0, -52);
  chunks_ = (rows() + kScanLanes - 1) / kScanLanes;
  const std::size_t chunk_floats = static_cast<std::size_t>(d) * kScanLanes;
  chunks_per_tile_ = std::max<std::int64_t>(
      1, static_cast<std::int64_t>(kTileBytes / (chunk_floats * sizeof(float))));
  lane_blocks_.assign(static_cast<std::size_t>(chunks_) * chunk_floats,
                      std::numeric_limits<float>::infinity()); // padding lanes never hit
  const float* values = this->table().values.data();
  for (std::int64_t row = 0; row < rows(); ++row) {
    float* chunk = lane_blocks_.data() + (row / kScanLanes) * chunk_floats;
    for (int c = 0; c < d; ++c)
      chunk[c * kScanLanes + row % kScanLanes] = values[row * d + c];
  }
}

float ExhaustiveSearch::threshold(const QueryState& state) const {
  const double radius = std::sqrt(state.best_distance) * (1.0 + kappa_) + state.rounding;
  return float_bound_.threshold(radius * radius, true);
}

void ExhaustiveSearch::accept_hits(QueryState& state, std::int64_t chunk,
                                   const float* distances) const {
  const int d = dimension();
  const float* chunk_values = lane_blocks_.data() + chunk * d * kScanLanes;
  for (unsigned below = lanes_below(distances, state.threshold); below != 0; below &= below - 1) {
    const int lane = __builtin_ctz(below);
    if (!(distances[lane] < state.threshold)) // an earlier lane lowered the threshold
      continue;
    const std::int64_t row = chunk * kScanLanes + lane;
    // The values from the lane block just scanned (in cache): same floats, same order as
    // distance2.
    const double exact = exact_distance2(chunk_values + lane, kScanLanes, state.query, d);
    if (state.best < 0 || exact < state.best_distance ||
        (exact == state.best_distance && row < state.best)) {
      state.best = row;
      state.best_distance = exact;
      state.threshold = threshold(state);
    }
  }
}

void ExhaustiveSearch::scan(QueryState& state, std::int64_t chunk_begin,
                            std::int64_t chunk_end) const {
  struct HitContext {
    const ExhaustiveSearch* self;
    QueryState* state;
  } context{this, &state};
  FloatDistanceScan scan;
  scan.lane_blocks = lane_blocks_.data();
  scan.chunk_begin = chunk_begin;
  scan.chunk_end = chunk_end;
  scan.channels = dimension();
  scan.query_features = state.floats.data();
  scan.thresholds = &state.threshold;
  scan.on_hit = [](void* c, std::int64_t chunk, const float* distances) {
    auto* hit = static_cast<HitContext*>(c);
    hit->self->accept_hits(*hit->state, chunk, distances);
  };
  scan.context = &context;
  scan_float_distances(ScanKernel::kSingle, scan);
}

void ExhaustiveSearch::nearest_batch(std::span<const double> queries,
                                     std::span<std::int64_t> rows) const {
  const int d = dimension();
  const auto count = static_cast<std::int64_t>(rows.size());
  TEXSIM_VERIFY(queries.size() == rows.size() * static_cast<std::size_t>(d),
                "neighbourhood search: " << queries.size() << " query values for " << count
                                         << " queries of " << d);
  std::vector<QueryState> states(rows.size());
  for (std::size_t i = 0; i < states.size(); ++i) {
    const auto query =
        queries.subspan(i * static_cast<std::size_t>(d), static_cast<std::size_t>(d));
    check_query(query);
    QueryState& state = states[i];
    state.query = query.data();
    state.floats.resize(static_cast<std::size_t>(d));
    double rounding = 0.0;
    for (int c = 0; c < d; ++c) {
      TEXSIM_VERIFY(std::abs(query[c]) <= safe_value_,
                    "neighbourhood search: query value " << query[c] << " exceeds " << safe_value_);
      state.floats[c] = static_cast<float>(query[c]);
      const double error = query[c] - static_cast<double>(state.floats[c]); // exact in double
      rounding += error * error;
    }
    state.rounding = std::sqrt(rounding) * (1.0 + kappa_);
  }
  // Threads take equal runs of queries; within a run, a tile of the table stays in cache while
  // every query scans it. Each answer is its query's exact argmin, whatever the thread count.
#pragma omp parallel if (count > 1)
  {
    const std::int64_t threads = omp_get_num_threads(), thread = omp_get_thread_num();
    const std::int64_t first = count * thread / threads;
    const std::int64_t last = count * (thread + 1) / threads;
    for (std::int64_t tile = 0; tile < chunks_; tile += chunks_per_tile_)
      for (std::int64_t i = first; i < last; ++i)
        scan(states[static_cast<std::size_t>(i)], tile, std::min(chunks_, tile + chunks_per_tile_));
  }
  for (std::size_t i = 0; i < states.size(); ++i)
    rows[i] = states[i].best;
}

std::int64_t ExhaustiveSearch::nearest(std::span<const double> query) const {
  std::int64_t row = -1;
  nearest_batch(query, std::span<std::int64_t>(&row, 1));
  return row;
}

std::size_t ExhaustiveSearch::memory_bytes() const {
  return table().values.capacity() * sizeof(float) + lane_blocks_.capacity() * sizeof(float);
}

} // namespace texsim::pipelines::surface_synthesis
