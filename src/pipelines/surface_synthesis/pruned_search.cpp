#include "pipelines/surface_synthesis/pruned_search.hpp"

#include "core/error.hpp"

#include <Eigen/Dense>
#include <nanoflann.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr int kPrunedSeeds = 4; ///< nearest keys whose full distance sets the first radius

/// nanoflann's view of the keys.
struct KeyCloud {
  const std::vector<double>* keys = nullptr;
  std::size_t width = 0;
  std::size_t kdtree_get_point_count() const { return keys->size() / width; }
  double kdtree_get_pt(std::uint32_t i, std::size_t k) const { return (*keys)[i * width + k]; }
  template <class Box> bool kdtree_get_bbox(Box&) const { return false; }
};

using KeyTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, KeyCloud>,
                                                    KeyCloud, -1, std::uint32_t>;

} // namespace

struct PrunedSearch::Index {
  KeyCloud cloud;
  KeyTree tree;
  Index(const std::vector<double>& keys, int width)
      : cloud{&keys, static_cast<std::size_t>(width)},
        tree(width, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {} // builds the tree
};

PrunedSearch::PrunedSearch(NeighbourhoodTable table, int components)
    : NeighbourhoodSearch(std::move(table)) {
  TEXSIM_VERIFY(components >= 1, "pruned search: " << components << " components, expected >= 1");
  TEXSIM_VERIFY(rows() < std::int64_t{1} << 32, "pruned search: " << rows() << " rows");
  const int d = dimension();
  components_ = std::min(components, d);
  const float* values = this->table().values.data();

  // Mean and covariance, summed in row order (the same bytes for any thread count).
  mean_.assign(static_cast<std::size_t>(d), 0.0);
  for (std::int64_t r = 0; r < rows(); ++r)
    for (int c = 0; c < d; ++c)
      mean_[c] += values[r * d + c];
  for (double& m : mean_)
    m /= static_cast<double>(rows());
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(d, d);
  std::vector<double> centred(static_cast<std::size_t>(d));
  for (std::int64_t r = 0; r < rows(); ++r) {
    for (int c = 0; c < d; ++c)
      centred[c] = values[r * d + c] - mean_[c];
    for (int j = 0; j < d; ++j)
      for (int i = j; i < d; ++i)
        covariance(i, j) += centred[i] * centred[j];
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance,
                                                              Eigen::ComputeEigenvectors);
  TEXSIM_VERIFY(solver.info() == Eigen::Success, "pruned search: PCA did not converge");

  // Leading axes (eigenvalues ascend), each signed so its largest entry is positive.
  basis_.resize(static_cast<std::size_t>(components_) * d);
  for (int k = 0; k < components_; ++k) {
    const auto axis = solver.eigenvectors().col(d - 1 - k);
    int largest = 0;
    for (int c = 1; c < d; ++c)
      if (std::abs(axis(c)) > std::abs(axis(largest)))
        largest = c;
    const double sign = axis(largest) < 0.0 ? -1.0 : 1.0;
    for (int c = 0; c < d; ++c)
      basis_[static_cast<std::size_t>(k) * d + c] = sign * axis(c);
  }

  const int width = components_ + 1;
  keys_.resize(static_cast<std::size_t>(rows()) * width);
  std::vector<double> row(static_cast<std::size_t>(d));
  for (std::int64_t r = 0; r < rows(); ++r) {
    std::copy(values + r * d, values + (r + 1) * d, row.begin());
    double norm = 0.0;
    key_of(row.data(), keys_.data() + r * width, norm);
    largest_norm_ = std::max(largest_norm_, norm);
  }
  index_ = std::make_unique<Index>(keys_, width);
}

PrunedSearch::~PrunedSearch() = default;

void PrunedSearch::key_of(const double* vector, double* key, double& norm) const {
  const int d = dimension();
  std::vector<double> rest(static_cast<std::size_t>(d));
  double norm2 = 0.0;
  for (int c = 0; c < d; ++c) {
    rest[c] = vector[c] - mean_[c];
    norm2 += rest[c] * rest[c];
  }
  norm = std::sqrt(norm2);
  for (int k = 0; k < components_; ++k) {
    const double* axis = basis_.data() + static_cast<std::size_t>(k) * d;
    double p = 0.0;
    for (int c = 0; c < d; ++c)
      p += axis[c] * (vector[c] - mean_[c]);
    key[k] = p;
    for (int c = 0; c < d; ++c)
      rest[c] -= p * axis[c];
  }
  double rho2 = 0.0;
  for (const double r : rest)
    rho2 += r * r;
  key[components_] = std::sqrt(rho2);
}

std::vector<std::int64_t> PrunedSearch::candidates(std::span<const double> query) const {
  check_query(query);
  const int d = dimension();
  std::vector<double> key(static_cast<std::size_t>(components_) + 1);
  double norm = 0.0;
  key_of(query.data(), key.data(), norm);

  std::uint32_t seeds[kPrunedSeeds];
  double seed_keys[kPrunedSeeds];
  const auto found = index_->tree.knnSearch(key.data(), kPrunedSeeds, seeds, seed_keys);
  double best = DBL_MAX;
  for (std::size_t i = 0; i < found; ++i)
    best = std::min(best, distance2(seeds[i], query));

  // Rounding of the keys: each is a sum of d + m products of terms bounded by the norms; 64 times
  // that bound for margin.
  const double key_error =
      64.0 * (d + components_ + 2) * std::ldexp(1.0, -53) * (largest_norm_ + norm);
  const double radius = std::sqrt(best) * (1.0 + 1e-9) + key_error;
  std::vector<std::pair<std::uint32_t, double>> matches;
  index_->tree.radiusSearch(key.data(), std::max(radius * radius, DBL_MIN), matches,
                            nanoflann::SearchParams(32, 0.0f, false));
  std::vector<std::int64_t> rows(matches.size());
  std::transform(matches.begin(), matches.end(), rows.begin(),
                 [](const auto& match) { return static_cast<std::int64_t>(match.first); });
  return rows;
}

std::int64_t PrunedSearch::nearest(std::span<const double> query) const {
  return nearest_among(candidates(query), query);
}

std::size_t PrunedSearch::memory_bytes() const {
  // nanoflann's node pool and row indices (usedMemory takes a mutable tree but only reads it).
  const std::size_t tree = index_->tree.pool.usedMemory + index_->tree.pool.wastedMemory +
                           static_cast<std::size_t>(rows()) * sizeof(std::uint32_t);
  return table().values.capacity() * sizeof(float) +
         (mean_.capacity() + basis_.capacity() + keys_.capacity()) * sizeof(double) + tree;
}

} // namespace texsim::pipelines::surface_synthesis
