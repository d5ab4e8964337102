#pragma once
/// Exact nearest neighbourhood by lower bounds (a modern alternative to Wei-Levoy's exhaustive
/// search): the rows are centred and rotated onto their principal axes (PCA, Eigen); the leading m
/// components p and the norm rho of the remainder form an (m + 1)-dimensional key, indexed in a
/// nanoflann kd-tree. For an orthonormal basis,
///   |x - q|^2 = |p(x) - p(q)|^2 + |rest(x) - rest(q)|^2 >= |p(x) - p(q)|^2 + (rho(x) - rho(q))^2,
/// so the key distance is a lower bound of the full one. A query takes the best full distance D
/// among its kPrunedSeeds nearest keys, then every row whose key lies within sqrt(D) (inflated by
/// a relative 1e-9 for the basis' orthonormality and the kd-tree's rounding, and by a generous
/// multiple of the rounding of the keys, which scales with the vectors' norms) gets its full
/// double distance in the original space, computed by distance2 like the exhaustive search: the
/// argmin, ties to the lower row, is the exhaustive search's answer.
///
/// m = 8 by default: on 64 x 64 exemplar neighbourhoods of 171 values the leading 8 components
/// carry most of the variance, and the kd-tree stays efficient in 9 dimensions.
#include "pipelines/surface_synthesis/neighbourhood_search.hpp"

#include <memory>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

class PrunedSearch final : public NeighbourhoodSearch {
public:
  /// Builds the PCA basis and the kd-tree; `components` (>= 1) is clamped to the dimension.
  PrunedSearch(NeighbourhoodTable table, int components);
  ~PrunedSearch() override;

  std::int64_t nearest(std::span<const double> query) const override;
  std::size_t memory_bytes() const override;

  /// The rows whose full distance nearest() compares (every row that can be the argmin), in
  /// kd-tree order.
  std::vector<std::int64_t> candidates(std::span<const double> query) const;
  /// Leading components indexed (m).
  int components() const { return components_; }

private:
  struct Index;
  /// The key of a vector (m components, then rho) and its centred norm.
  void key_of(const double* vector, double* key, double& norm) const;

  int components_ = 0;
  std::vector<double> mean_;
  std::vector<double> basis_; ///< components x dimension, row-major: the leading principal axes
  std::vector<double> keys_;  ///< rows x (components + 1)
  double largest_norm_ = 0.0; ///< max over rows of |x - mean|
  std::unique_ptr<Index> index_;
};

} // namespace texsim::pipelines::surface_synthesis
