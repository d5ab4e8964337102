#include "pipelines/surface_synthesis/exhaustive_search.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr std::size_t kTileBytes = 128 * 1024; ///< lane blocks scanned per pass over the queries

} // namespace

/// Up to kScanQueries queries scanned together: their float copies, rounding radii, thresholds
/// and best rows so far.
struct ExhaustiveSearch::Block {
  int count = 0;
  const double* queries[kScanQueries] = {};
  std::vector<float> query_floats;    ///< kScanQueries x dimension
  double rounding[kScanQueries] = {}; ///< |q - float(q)|, rounded up
  float thresholds[kScanQueries] = {};
  std::int64_t best[kScanQueries] = {};
  double best_distance[kScanQueries] = {};
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

float ExhaustiveSearch::threshold(const Block& block, int slot) const {
  if (block.best[slot] < 0)
    return kScanNoBound;
  const double radius =
      std::sqrt(block.best_distance[slot]) * (1.0 + kappa_) + block.rounding[slot];
  return float_bound_.threshold(radius * radius, true);
}

void ExhaustiveSearch::accept_hits(Block& block, std::int64_t chunk, const float* distances) const {
  const int d = dimension();
  const float* chunk_values = lane_blocks_.data() + chunk * d * kScanLanes;
  for (int j = 0; j < block.count; ++j) {
    const float* lanes = distances + j * kScanLanes;
    for (unsigned below = lanes_below(lanes, block.thresholds[j]); below != 0; below &= below - 1) {
      const int lane = __builtin_ctz(below);
      if (!(lanes[lane] < block.thresholds[j])) // an earlier lane lowered the threshold
        continue;
      const std::int64_t row = chunk * kScanLanes + lane;
      // The values from the lane block just scanned (in cache): same floats, same order as
      // distance2.
      const double exact = exact_distance2(chunk_values + lane, kScanLanes, block.queries[j], d);
      if (block.best[j] < 0 || exact < block.best_distance[j] ||
          (exact == block.best_distance[j] && row < block.best[j])) {
        block.best[j] = row;
        block.best_distance[j] = exact;
        block.thresholds[j] = threshold(block, j);
      }
    }
  }
}

void ExhaustiveSearch::scan_block(Block& block, std::int64_t chunk_begin,
                                  std::int64_t chunk_end) const {
  struct HitContext {
    const ExhaustiveSearch* self;
    Block* block;
  } context{this, &block};
  FloatDistanceScan scan;
  scan.lane_blocks = lane_blocks_.data();
  scan.chunk_begin = chunk_begin;
  scan.chunk_end = chunk_end;
  scan.channels = dimension();
  scan.query_features = block.query_floats.data();
  scan.thresholds = block.thresholds;
  scan.on_hit = [](void* c, std::int64_t chunk, const float* distances) {
    auto* hit = static_cast<HitContext*>(c);
    hit->self->accept_hits(*hit->block, chunk, distances);
  };
  scan.context = &context;
  scan_float_distances(scan);
}

void ExhaustiveSearch::nearest_batch(std::span<const double> queries,
                                     std::span<std::int64_t> rows) const {
  const int d = dimension();
  const auto count = static_cast<std::int64_t>(rows.size());
  TEXSIM_VERIFY(queries.size() == rows.size() * static_cast<std::size_t>(d),
                "neighbourhood search: " << queries.size() << " query values for " << count
                                         << " queries of " << d);
  std::vector<Block> blocks(static_cast<std::size_t>((count + kScanQueries - 1) / kScanQueries));
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    Block& block = blocks[b];
    block.count = static_cast<int>(
        std::min<std::int64_t>(kScanQueries, count - static_cast<std::int64_t>(b) * kScanQueries));
    block.query_floats.assign(static_cast<std::size_t>(kScanQueries) * d, 0.0f);
    for (int j = 0; j < kScanQueries; ++j) {
      block.thresholds[j] = kScanNeverHits;
      block.best[j] = -1;
      if (j >= block.count)
        continue;
      const auto query = queries.subspan((b * kScanQueries + j) * static_cast<std::size_t>(d),
                                         static_cast<std::size_t>(d));
      check_query(query);
      double rounding = 0.0;
      for (int c = 0; c < d; ++c) {
        TEXSIM_VERIFY(std::abs(query[c]) <= safe_value_, "neighbourhood search: query value "
                                                             << query[c] << " exceeds "
                                                             << safe_value_);
        const float f = static_cast<float>(query[c]);
        block.query_floats[static_cast<std::size_t>(j) * d + c] = f;
        const double error = query[c] - static_cast<double>(f); // exact in double
        rounding += error * error;
      }
      block.queries[j] = query.data();
      block.rounding[j] = std::sqrt(rounding) * (1.0 + kappa_);
      block.thresholds[j] = kScanNoBound;
    }
  }
  // Tiles of the table stay in cache while every block scans them.
  for (std::int64_t tile = 0; tile < chunks_; tile += chunks_per_tile_)
    for (Block& block : blocks)
      scan_block(block, tile, std::min(chunks_, tile + chunks_per_tile_));
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (int j = 0; j < blocks[b].count; ++j)
      rows[b * kScanQueries + j] = blocks[b].best[j];
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
