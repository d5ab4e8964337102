#pragma once
/// Exact nearest neighbourhood by a full scan (Wei-Levoy's exhaustive search), made fast by
/// core/float_distance_scan: float distances of a query to 16 rows at a time (its one-query
/// kernel: measured on AVX2, 57 us per query against 207 us for the 8-query block kernel, whose
/// 8 x 16 accumulators spill there), and only rows whose float distance may hide an exact distance
/// within the best one found so far get their exact double distance. Batches share cache tiles
/// of the table and split over OpenMP threads.
///
/// Why the skipped rows are provably worse: the scan works with the query q rounded to float, q'.
/// With eps = |q - q'| (computed per query), the triangle inequality gives
/// sqrt(D(r, q)) >= sqrt(D(r, q')) - eps. A row is skipped only when its float distance to q' is at
/// or above FloatDistanceBound's threshold for (sqrt(best) (1 + kappa) + eps)^2, i.e. when its
/// exact distance to q' exceeds that bound; then D(r, q) > best (1 + kappa)^2, and kappa covers the
/// rounding of the double distances, so the row's computed distance is strictly above the best
/// one. The result is the exact argmin of the double distances, ties to the lower row.
#include "core/float_distance_scan.hpp"
#include "pipelines/surface_synthesis/neighbourhood_search.hpp"

#include <vector>

namespace texsim::pipelines::surface_synthesis {

class ExhaustiveSearch final : public NeighbourhoodSearch {
public:
  /// Copies the table into 16-row lane blocks. Values must be small enough that float squared
  /// distances cannot overflow (|value| <= sqrt(FLT_MAX / (16 dimension)), 3.5e17 for 171 values).
  explicit ExhaustiveSearch(NeighbourhoodTable table);

  std::int64_t nearest(std::span<const double> query) const override;
  void nearest_batch(std::span<const double> queries, std::span<std::int64_t> rows) const override;
  std::size_t memory_bytes() const override;

private:
  struct QueryState;
  void scan(QueryState& state, std::int64_t chunk_begin, std::int64_t chunk_end) const;
  void accept_hits(QueryState& state, std::int64_t chunk, const float* distances) const;
  float threshold(const QueryState& state) const;

  std::int64_t chunks_ = 0;
  std::int64_t chunks_per_tile_ = 1;
  double kappa_ = 0.0;
  FloatDistanceBound float_bound_;
  float safe_value_ = 0.0f;
  std::vector<float> lane_blocks_; ///< per 16-row chunk: dimension-major, 16 lanes each
};

} // namespace texsim::pipelines::surface_synthesis
