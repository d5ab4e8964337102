#include "pipelines/solid_synthesis/synthesis_metrics.hpp"

#include "core/error.hpp"
#include "img/colour_histogram.hpp"
#include "pipelines/solid_synthesis/distinct_features.hpp"
#include "pipelines/solid_synthesis/feature_kd_tree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Mean Euclidean distance of the rows of `vectors` (count x dimension) to their mean.
double mean_spread(std::span<const float> vectors, int dimension) {
  const std::size_t count = vectors.size() / static_cast<std::size_t>(dimension);
  std::vector<double> mean(dimension, 0.0);
  for (std::size_t v = 0; v < count; ++v) {
    for (int c = 0; c < dimension; ++c) {
      mean[c] += vectors[v * dimension + c];
    }
  }
  for (double& m : mean) {
    m /= static_cast<double>(count);
  }
  double sum = 0.0;
  for (std::size_t v = 0; v < count; ++v) {
    double squared = 0.0;
    for (int c = 0; c < dimension; ++c) {
      const double d = vectors[v * dimension + c] - mean[c];
      squared += d * d;
    }
    sum += std::sqrt(squared);
  }
  return sum / static_cast<double>(count);
}

/// Lowers its radius to the nearest distance found so far: the tree then visits only the voxels
/// that can still beat it.
class NearestVisitor final : public FeatureVisitor {
public:
  NearestVisitor(const vol::ChannelGrid& features, const float* query)
      : features_(features), query_(query) {}
  /// Once a voxel matches exactly nothing can beat it: a negative radius ends the search.
  double radius() const override { return nearest_ > 0.0 ? nearest_ : -1.0; }
  void visit(std::int32_t voxel) override {
    nearest_ = std::min(nearest_, exact_feature_distance(features_.voxel(std::size_t(voxel)).data(),
                                                         1, query_, features_.channels()));
  }
  double nearest() const { return nearest_; }

private:
  const vol::ChannelGrid& features_;
  const float* query_;
  double nearest_ = std::numeric_limits<double>::infinity();
};

double luminance(std::span<const float> colour) {
  return colour.size() == 1 ? colour[0]
                            : 0.2126 * colour[0] + 0.7152 * colour[1] + 0.0722 * colour[2];
}

/// Nearest distances through `tree`, or by scanning every voxel when it is null.
std::vector<double> nearest_distances(std::span<const float> queries,
                                      const vol::ChannelGrid& exemplar_features,
                                      const FeatureKdTree* tree) {
  const int dimension = exemplar_features.channels();
  const auto count = static_cast<std::int64_t>(queries.size() / std::size_t(dimension));
  std::vector<double> distances(static_cast<std::size_t>(count));
#pragma omp parallel for schedule(dynamic, 64)
  for (std::int64_t q = 0; q < count; ++q) {
    const float* query = queries.data() + q * dimension;
    NearestVisitor nearest(exemplar_features, query);
    if (tree)
      tree->search(query, nearest);
    else
      for (std::size_t v = 0; v < exemplar_features.voxel_count(); ++v)
        nearest.visit(static_cast<std::int32_t>(v));
    distances[std::size_t(q)] = std::sqrt(nearest.nearest());
  }
  return distances;
}

} // namespace

double appearance_spread(const vol::ChannelGrid& exemplar_features) {
  const double spread = mean_spread(exemplar_features.data(), exemplar_features.channels());
  TEXSIM_VERIFY(spread > 0.0, "neighbourhood_error: the exemplar's appearance vectors are all "
                              "equal, so the error has no scale");
  return spread;
}

std::vector<double> nearest_appearance_distances(std::span<const float> queries,
                                                 const vol::ChannelGrid& exemplar_features) {
  // Exact nearest neighbours through the kd-tree the similarity sets use, over each distinct
  // vector once: on appearance features it visits a few hundred of them per query instead of all.
  // Wider vectors (raw neighbourhoods) than the tree indexes are scanned in full.
  const vol::ChannelGrid distinct = distinct_feature_rows(exemplar_features);
  if (distinct.channels() > FeatureKdTree::kMaxChannels)
    return nearest_distances(queries, distinct, nullptr);
  const FeatureKdTree tree(distinct);
  return nearest_distances(queries, distinct, &tree);
}

std::vector<double> nearest_appearance_distances(std::span<const float> queries,
                                                 const vol::ChannelGrid& exemplar_features,
                                                 const FeatureKdTree& tree) {
  return nearest_distances(queries, exemplar_features, &tree);
}

double neighbourhood_error(const vol::ChannelGrid& result_colours,
                           const vol::ChannelGrid& exemplar_features,
                           const NeighbourhoodProjection& project, int stride) {
  TEXSIM_VERIFY(stride > 0, "neighbourhood_error: stride must be positive, got " << stride);
  const int dimension = exemplar_features.channels();
  const double spread = appearance_spread(exemplar_features);

  const vol::Dims dims = result_colours.dims();
  std::vector<std::array<int, 3>> samples;
  for (int k = 0; k < dims.nz; k += stride) {
    for (int j = 0; j < dims.ny; j += stride) {
      for (int i = 0; i < dims.nx; i += stride) {
        samples.push_back({i, j, k});
      }
    }
  }
  const auto count = static_cast<std::int64_t>(samples.size());
  std::vector<float> queries(samples.size() * static_cast<std::size_t>(dimension));
#pragma omp parallel for schedule(static)
  for (std::int64_t q = 0; q < count; ++q) {
    const auto& [i, j, k] = samples[q];
    project(result_colours, i, j, k,
            std::span<float>(queries.data() + q * dimension, static_cast<std::size_t>(dimension)));
  }
  double sum = 0.0;
  for (const double distance : nearest_appearance_distances(queries, exemplar_features)) {
    sum += distance;
  }
  return sum / static_cast<double>(count) / spread;
}

double histogram_distance(const vol::ChannelGrid& a, const vol::ChannelGrid& b) {
  TEXSIM_VERIFY(a.channels() == b.channels(),
                "histogram_distance needs grids with the same channels, got "
                    << a.channels() << " and " << b.channels());
  return img::histogram_distance(a.data(), b.data(), a.channels());
}

double xy_stripe_orientation_degrees(const vol::ChannelGrid& colours) {
  TEXSIM_VERIFY(colours.channels() == 1 || colours.channels() == 3,
                "xy_stripe_orientation_degrees needs 1 or 3 channels, got " << colours.channels());
  const vol::Dims dims = colours.dims();
  const auto at = [&](int i, int j, int k) {
    return luminance(colours.voxel(colours.periodic_index(i, j, k)));
  };
  double xx = 0.0, xy = 0.0, yy = 0.0;
  for (int k = 0; k < dims.nz; ++k) {
    for (int j = 0; j < dims.ny; ++j) {
      for (int i = 0; i < dims.nx; ++i) {
        const double gx = 0.5 * (at(i + 1, j, k) - at(i - 1, j, k));
        const double gy = 0.5 * (at(i, j + 1, k) - at(i, j - 1, k));
        xx += gx * gx;
        xy += gx * gy;
        yy += gy * gy;
      }
    }
  }
  // The tensor's major eigenvector is the dominant gradient direction; stripes run across it.
  const double gradient = 0.5 * std::atan2(2.0 * xy, xx - yy) * 180.0 / std::numbers::pi;
  double stripes = gradient + 90.0;
  if (stripes > 90.0) {
    stripes -= 180.0;
  }
  return stripes;
}

} // namespace texsim::pipelines::solid_synthesis
