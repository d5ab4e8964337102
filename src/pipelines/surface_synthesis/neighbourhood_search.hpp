#pragma once
/// Nearest-neighbourhood search over an exemplar's neighbourhood vectors (Wei-Levoy's matching
/// step): given a query vector, the exemplar pixel whose neighbourhood is nearest in squared L2
/// distance. Three methods: `exhaustive` (exact, a certified float scan, exhaustive_search.hpp),
/// `tsvq` (Wei-Levoy 2000's tree-structured vector quantiser, approximate, tsvq_tree.hpp) and
/// `pruned` (exact: PCA lower bounds in a kd-tree, pruned_search.hpp).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

enum class SearchMethod { exhaustive, tsvq, pruned };

/// Candidates: `rows` neighbourhood vectors of `dimension` values each, row-major floats
/// (row r = exemplar pixel r, so ties to the lower row = ties to the lower pixel).
struct NeighbourhoodTable {
  int dimension = 0;
  std::vector<float> values;
  std::int64_t rows() const {
    return dimension > 0 ? static_cast<std::int64_t>(values.size()) / dimension : 0;
  }
};

/// Tuning of the approximate and pruned methods; the defaults are the documented ones.
struct SearchOptions {
  /// TSVQ: a node with at most this many rows is a leaf, scanned exactly. 1 = Wei-Levoy 2000 (one
  /// neighbourhood per leaf); >= rows: one leaf, so TSVQ returns exactly what exhaustive returns.
  std::int64_t tsvq_leaf_size = 1;
  /// TSVQ: Lloyd iterations per 2-means split (fewer if the assignment stops changing).
  int tsvq_iterations = 10;
  /// pruned: leading PCA components indexed by the kd-tree (clamped to the dimension).
  int pruned_components = 8;
};

/// A built search over one table. All queries are const and thread-safe.
class NeighbourhoodSearch {
public:
  explicit NeighbourhoodSearch(NeighbourhoodTable table);
  virtual ~NeighbourhoodSearch();
  NeighbourhoodSearch(const NeighbourhoodSearch&) = delete;
  NeighbourhoodSearch& operator=(const NeighbourhoodSearch&) = delete;

  /// The row nearest to `query` (size dimension) in squared L2 distance accumulated in double;
  /// exhaustive and pruned: the exact argmin, ties to the lower row. Thread-safe.
  virtual std::int64_t nearest(std::span<const double> query) const = 0;
  /// nearest() of each of rows.size() queries stored back to back in `queries` (rows.size() x
  /// dimension values). The same answers as one nearest() call per query; exhaustive scans the
  /// table once per 8 queries, so batches are much faster there, and splits a batch over the
  /// OpenMP threads. Thread-safe.
  virtual void nearest_batch(std::span<const double> queries, std::span<std::int64_t> rows) const;
  /// Squared distance from query to a row, computed exactly as the exhaustive search does: the
  /// sum over c in order of (double(value_c) - query_c)^2.
  double distance2(std::int64_t row, std::span<const double> query) const;
  /// Bytes held by the search (table, copies and index).
  virtual std::size_t memory_bytes() const = 0;

  int dimension() const { return table_.dimension; }
  std::int64_t rows() const { return table_.rows(); }
  const NeighbourhoodTable& table() const { return table_; }

protected:
  /// The exact argmin of distance2 over `candidates` (any order), ties to the lower row.
  std::int64_t nearest_among(std::span<const std::int64_t> candidates,
                             std::span<const double> query) const;
  /// Throws unless query.size() == dimension and every value is finite.
  void check_query(std::span<const double> query) const;

private:
  NeighbourhoodTable table_;
};

/// Builds the search of `method` over `table` (taken by value: pass it moved). Throws if the table
/// is empty, its size is not rows x dimension or a value is not finite.
std::unique_ptr<NeighbourhoodSearch> make_neighbourhood_search(SearchMethod method,
                                                               NeighbourhoodTable table,
                                                               const SearchOptions& options = {});

/// Squared L2 distance of a float vector (value c at row[c * stride]) to a double query, summed
/// in double in channel order: the one distance every method compares.
inline double exact_distance2(const float* row, std::ptrdiff_t stride, const double* query,
                              int dimension) {
  double sum = 0.0;
  for (int c = 0; c < dimension; ++c) {
    const double diff = static_cast<double>(row[c * stride]) - query[c];
    sum += diff * diff;
  }
  return sum;
}

} // namespace texsim::pipelines::surface_synthesis
