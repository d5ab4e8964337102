#include "pipelines/solid_synthesis/synthesis_metrics.hpp"

#include "core/error.hpp"
#include "img/colour_histogram.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
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

/// Exemplar points per block of the nearest-neighbour scan: the block's columns stay in cache
/// while a group of queries is compared with them.
constexpr std::size_t kPointBlock = 256;
/// Queries handled together against one block of points.
constexpr std::int64_t kQueryGroup = 64;
/// Points compared with a query at once: one AVX-512 register (two AVX2 ones).
constexpr std::size_t kLanes = 16;
using Lanes = float __attribute__((vector_size(kLanes * sizeof(float))));

/// For each of `query_count` queries (rows of `queries`, `dimension` floats each), lowers
/// best[q] to the smallest squared distance to the points [begin, end) of `columns` (the exemplar
/// transposed: channel c of point v at columns[c * points + v]). Squares of float differences, so
/// a query equal to a point gives exactly 0.
__attribute__((target_clones("avx512f", "avx2", "default"))) void
lower_to_nearest(const float* columns, std::size_t points, std::size_t begin, std::size_t end,
                 int dimension, const float* queries, std::int64_t query_count, float* best) {
  const std::size_t vector_end = begin + (end - begin) / kLanes * kLanes;
  for (std::int64_t q = 0; q < query_count; ++q) {
    const float* query = queries + q * dimension;
    Lanes nearest_lanes;
    for (std::size_t l = 0; l < kLanes; ++l) {
      nearest_lanes[l] = best[q];
    }
    for (std::size_t v = begin; v < vector_end; v += kLanes) {
      Lanes squared = {};
      for (int c = 0; c < dimension; ++c) {
        Lanes values;
        std::memcpy(&values, columns + static_cast<std::size_t>(c) * points + v, sizeof(Lanes));
        const Lanes difference = values - query[c];
        squared += difference * difference;
      }
      nearest_lanes = squared < nearest_lanes ? squared : nearest_lanes;
    }
    float nearest = best[q];
    for (std::size_t l = 0; l < kLanes; ++l) {
      nearest = std::min(nearest, nearest_lanes[l]);
    }
    for (std::size_t v = vector_end; v < end; ++v) {
      float squared = 0.0f;
      for (int c = 0; c < dimension; ++c) {
        const float difference = columns[static_cast<std::size_t>(c) * points + v] - query[c];
        squared += difference * difference;
      }
      nearest = std::min(nearest, squared);
    }
    best[q] = nearest;
  }
}

double luminance(std::span<const float> colour) {
  return colour.size() == 1 ? colour[0]
                            : 0.2126 * colour[0] + 0.7152 * colour[1] + 0.0722 * colour[2];
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
  const int dimension = exemplar_features.channels();
  const std::span<const float> exemplar = exemplar_features.data();
  const auto count = static_cast<std::int64_t>(queries.size() / std::size_t(dimension));
  // Exact nearest neighbours by a blocked brute-force scan over the exemplar transposed, so each
  // channel's values are contiguous and the distance loop runs across points in SIMD lanes.
  const std::size_t points = exemplar_features.voxel_count();
  std::vector<float> columns(exemplar.size());
  for (std::size_t v = 0; v < points; ++v) {
    for (int c = 0; c < dimension; ++c) {
      columns[static_cast<std::size_t>(c) * points + v] = exemplar[v * dimension + c];
    }
  }
  std::vector<float> best(static_cast<std::size_t>(count), std::numeric_limits<float>::infinity());
  const std::int64_t groups = (count + kQueryGroup - 1) / kQueryGroup;
#pragma omp parallel for schedule(dynamic)
  for (std::int64_t group = 0; group < groups; ++group) {
    const std::int64_t first = group * kQueryGroup;
    const std::int64_t size = std::min(kQueryGroup, count - first);
    for (std::size_t begin = 0; begin < points; begin += kPointBlock) {
      lower_to_nearest(columns.data(), points, begin, std::min(points, begin + kPointBlock),
                       dimension, queries.data() + first * dimension, size, best.data() + first);
    }
  }
  std::vector<double> distances(best.size());
  std::transform(best.begin(), best.end(), distances.begin(),
                 [](float squared) { return std::sqrt(static_cast<double>(squared)); });
  return distances;
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
