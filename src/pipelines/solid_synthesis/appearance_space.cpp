#include "pipelines/solid_synthesis/appearance_space.hpp"

#include "core/error.hpp"
#include "par/comm.hpp"
#include "par/node_shared_array.hpp"
#include "vol/gaussian_stack_3d.hpp"
#include "vol/node_shared_grid.hpp"

#include <cblas.h>
#include <mpi.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

using RowMatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Neighbourhoods gathered per matrix product: enough rows for BLAS to run at speed, few enough
/// that a block (rows x 375 floats) stays in cache.
constexpr int kBlockVoxels = 256;
/// The covariance of clamped neighbourhoods is summed in this many partial sums, each over a fixed
/// range of blocks, then added in order: the result does not depend on the thread count.
constexpr int kCovarianceChunks = 16;
/// A direction whose variance is below components * (kRoundingUlps * FLT_EPSILON * largest
/// |value|)^2 holds float rounding noise (e.g. on the constant coarsest level), not structure.
constexpr double kRoundingUlps = 16.0;

/// The voxels of a stack level whose appearance vectors are computed, enumerated x fastest.
struct Box {
  std::array<int, 3> lo{};
  std::array<int, 3> size{};

  std::size_t count() const {
    return static_cast<std::size_t>(size[0]) * static_cast<std::size_t>(size[1]) *
           static_cast<std::size_t>(size[2]);
  }
  /// Grid coordinates of the m-th voxel of the box.
  std::array<int, 3> voxel(std::size_t m) const {
    const auto sx = static_cast<std::size_t>(size[0]), sy = static_cast<std::size_t>(size[1]);
    return {lo[0] + static_cast<int>(m % sx), lo[1] + static_cast<int>((m / sx) % sy),
            lo[2] + static_cast<int>(m / (sx * sy))};
  }
};

/// Per-channel mean over the box, summed per z-slice then over slices in order.
std::vector<double> channel_mean(const vol::ChannelGrid& grid, const Box& box) {
  const int channels = grid.channels();
  const auto c_count = static_cast<std::size_t>(channels);
  std::vector<double> slice_sums(static_cast<std::size_t>(box.size[2]) * c_count, 0.0);
#pragma omp parallel for schedule(static)
  for (int z = 0; z < box.size[2]; ++z) {
    double* sum = slice_sums.data() + static_cast<std::size_t>(z) * c_count;
    for (int y = 0; y < box.size[1]; ++y) {
      for (int x = 0; x < box.size[0]; ++x) {
        const auto v = grid.voxel(grid.index(box.lo[0] + x, box.lo[1] + y, box.lo[2] + z));
        for (std::size_t c = 0; c < c_count; ++c) {
          sum[c] += v[c];
        }
      }
    }
  }
  std::vector<double> mean(c_count, 0.0);
  for (int z = 0; z < box.size[2]; ++z) {
    for (std::size_t c = 0; c < c_count; ++c) {
      mean[c] += slice_sums[static_cast<std::size_t>(z) * c_count + c];
    }
  }
  for (double& m : mean) {
    m /= static_cast<double>(box.count());
  }
  return mean;
}

/// Reads window^3 neighbourhoods of a grid with taps `spacing` voxels apart, clamped at the faces.
/// Components are tap-major (z, y, x) with the channels fastest.
class ClampedNeighbourhoods {
public:
  ClampedNeighbourhoods(const vol::ChannelGrid& grid, int window, int spacing)
      : grid_(grid), window_(window) {
    const vol::Dims dims = grid.dims();
    const std::array<int, 3> n{dims.nx, dims.ny, dims.nz};
    for (std::size_t a = 0; a < 3; ++a) {
      extent_[a] = n[a];
      taps_[a].resize(static_cast<std::size_t>(window * n[a]));
      for (int t = 0; t < window; ++t) {
        for (int p = 0; p < n[a]; ++p) {
          const int q = p + (t - window / 2) * spacing;
          taps_[a][static_cast<std::size_t>(t * n[a] + p)] = vol::ChannelGrid::clamp(q, n[a]);
        }
      }
    }
  }

  /// The neighbourhood of voxel (i, j, k) minus `centre` (one value per channel).
  void gather(int i, int j, int k, const std::vector<float>& centre, float* out) const {
    const auto channels = centre.size();
    const auto nx = static_cast<std::size_t>(extent_[0]), ny = static_cast<std::size_t>(extent_[1]);
    for (int tz = 0; tz < window_; ++tz) {
      const auto z = static_cast<std::size_t>(tap(2, tz, k));
      for (int ty = 0; ty < window_; ++ty) {
        const std::size_t row = nx * (static_cast<std::size_t>(tap(1, ty, j)) + ny * z);
        for (int tx = 0; tx < window_; ++tx) {
          const auto v = grid_.voxel(row + static_cast<std::size_t>(tap(0, tx, i)));
          for (std::size_t c = 0; c < channels; ++c) {
            *out++ = v[c] - centre[c];
          }
        }
      }
    }
  }

private:
  int tap(std::size_t axis, int t, int p) const {
    return taps_[axis][static_cast<std::size_t>(t * extent_[axis] + p)];
  }

  const vol::ChannelGrid& grid_;
  int window_;
  std::array<int, 3> extent_{};
  std::array<std::vector<int>, 3> taps_; ///< taps_[axis][t * n + p]: coordinate tap t reads
};

/// Mean and covariance of a level's neighbourhood vectors, and the per-channel mean that gathered
/// neighbourhoods are centred on.
struct NeighbourhoodStatistics {
  std::vector<float> centre;
  Eigen::VectorXd mean;
  Eigen::MatrixXd covariance;
};

/// sum_i a[i] * b[i]: float products in 64 independent lanes (vectorised without reassociation,
/// several accumulators deep), the lanes added in double.
__attribute__((target_clones("avx512f", "avx2", "default"))) double
lane_dot(const float* a, const float* b, std::size_t n) {
  constexpr std::size_t kLanes = 64;
  float lanes[kLanes] = {};
  std::size_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    for (std::size_t l = 0; l < kLanes; ++l) {
      lanes[l] += a[i + l] * b[i + l];
    }
  }
  double sum = 0.0;
  for (std::size_t l = 0; l < kLanes; ++l) {
    sum += lanes[l];
  }
  for (; i < n; ++i) {
    sum += static_cast<double>(a[i]) * b[i];
  }
  return sum;
}

/// Toroidal neighbourhoods are stationary: the covariance of taps t1, t2 and channels c1, c2 is
/// the circular cross-correlation R_c1c2(h (t2 - t1)) of the centred channels. Only the
/// (2 window - 1)^3 distinct offsets (fewer once h wraps around the grid), half of them by
/// R_c1c2(-o) = R_c2c1(o), are summed over the grid, as long contiguous dot products, instead of
/// a (window^3 C)^2 product per voxel. The grid is walked one z-slice at a time, with centred
/// copies of only the slices that slice meets (one per z offset), not of the whole level.
NeighbourhoodStatistics toroidal_statistics(const vol::ChannelGrid& level, int window,
                                            int spacing) {
  const vol::Dims dims = level.dims();
  const std::array<int, 3> n{dims.nx, dims.ny, dims.nz};
  const int channels = level.channels();
  const auto c_count = static_cast<std::size_t>(channels);
  const std::size_t voxels = level.voxel_count();
  const std::vector<double> mean = channel_mean(level, Box{{0, 0, 0}, n});

  // Distinct wrapped offsets per axis: offset_index[a][e + window - 1] for tap difference e, and
  // the index of the opposite offset.
  std::array<std::vector<int>, 3> offsets;
  std::array<std::vector<std::size_t>, 3> offset_index, opposite;
  for (std::size_t a = 0; a < 3; ++a) {
    for (int e = -(window - 1); e < window; ++e) {
      const int shift = vol::ChannelGrid::wrap(e * spacing, n[a]);
      const auto found = std::find(offsets[a].begin(), offsets[a].end(), shift);
      offset_index[a].push_back(static_cast<std::size_t>(found - offsets[a].begin()));
      if (found == offsets[a].end()) {
        offsets[a].push_back(shift);
      }
    }
    for (const int shift : offsets[a]) {
      const int back = vol::ChannelGrid::wrap(-shift, n[a]);
      opposite[a].push_back(static_cast<std::size_t>(
          std::find(offsets[a].begin(), offsets[a].end(), back) - offsets[a].begin()));
    }
  }
  const std::size_t nx_offsets = offsets[0].size(), ny_offsets = offsets[1].size(),
                    nz_offsets = offsets[2].size();
  const auto combination = [&](std::size_t ox, std::size_t oy, std::size_t oz) {
    return (ox * ny_offsets + oy) * nz_offsets + oz;
  };
  const std::size_t pairs = c_count * c_count;
  // correlation[combination(ox, oy, oz) * pairs + c1 * C + c2]
  std::vector<double> correlation(nx_offsets * ny_offsets * nz_offsets * pairs);

  const auto nx = static_cast<std::size_t>(n[0]), ny = static_cast<std::size_t>(n[1]);
  const std::size_t slice = nx * ny;
  using SlicePlanes = std::vector<std::vector<float>>; // [channel][voxel of the slice]
  const auto centre_slice = [&](int z, SlicePlanes& out) {
    const std::size_t first = static_cast<std::size_t>(z) * slice;
#pragma omp parallel for schedule(static)
    for (std::size_t v = 0; v < slice; ++v) {
      const auto value = level.voxel(first + v);
      for (std::size_t c = 0; c < c_count; ++c) {
        out[c][v] = value[c] - static_cast<float>(mean[c]);
      }
    }
  };
  SlicePlanes a_slice(c_count, std::vector<float>(slice));
  // The slice z + offsets[2][oz] of each z offset, centred, and rolled along x by the x offset.
  std::vector<SlicePlanes> b_slices(nz_offsets, a_slice), rolled(nz_offsets, a_slice);
  const auto tasks = static_cast<std::ptrdiff_t>(ny_offsets * nz_offsets);
  for (int z = 0; z < n[2]; ++z) {
    centre_slice(z, a_slice);
    for (std::size_t oz = 0; oz < nz_offsets; ++oz) {
      centre_slice(vol::ChannelGrid::wrap(z + offsets[2][oz], n[2]), b_slices[oz]);
    }
    for (std::size_t ox = 0; ox < nx_offsets; ++ox) {
      // Rolled by the x offset, every offset with it becomes a plain elementwise product.
      const auto shift = static_cast<std::size_t>(offsets[0][ox]);
      const auto rows = static_cast<std::ptrdiff_t>(nz_offsets * ny);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t task = 0; task < rows; ++task) {
        const auto oz = static_cast<std::size_t>(task) / ny,
                   row = static_cast<std::size_t>(task) % ny;
        for (std::size_t c = 0; c < c_count; ++c) {
          const float* in = b_slices[oz][c].data() + row * nx;
          float* out = rolled[oz][c].data() + row * nx;
          std::copy(in + shift, in + nx, out);
          std::copy(in, in + shift, out + (nx - shift));
        }
      }
#pragma omp parallel for schedule(dynamic)
      for (std::ptrdiff_t task = 0; task < tasks; ++task) {
        const auto oz = static_cast<std::size_t>(task) % nz_offsets,
                   oy = static_cast<std::size_t>(task) / nz_offsets;
        if (combination(opposite[0][ox], opposite[1][oy], opposite[2][oz]) <
            combination(ox, oy, oz)) {
          continue; // filled in from the opposite offset below
        }
        const auto sy = static_cast<std::size_t>(offsets[1][oy]);
        // Rows y < ny - sy meet rows y + sy of the same slice, the others wrap to its start.
        const std::size_t straight = (ny - sy) * nx;
        double* sums = correlation.data() + combination(ox, oy, oz) * pairs;
        for (std::size_t c1 = 0; c1 < c_count; ++c1) {
          const float* a = a_slice[c1].data();
          for (std::size_t c2 = 0; c2 < c_count; ++c2) {
            const float* b = rolled[oz][c2].data();
            sums[c1 * c_count + c2] +=
                lane_dot(a, b + sy * nx, straight) + lane_dot(a + straight, b, sy * nx);
          }
        }
      }
    }
  }
  for (double& sum : correlation) {
    sum /= static_cast<double>(voxels);
  }
  for (std::size_t ox = 0; ox < nx_offsets; ++ox) {
    for (std::size_t oy = 0; oy < ny_offsets; ++oy) {
      for (std::size_t oz = 0; oz < nz_offsets; ++oz) {
        const std::size_t here = combination(ox, oy, oz);
        const std::size_t back = combination(opposite[0][ox], opposite[1][oy], opposite[2][oz]);
        if (back < here) {
          for (std::size_t c1 = 0; c1 < c_count; ++c1) {
            for (std::size_t c2 = 0; c2 < c_count; ++c2) {
              correlation[here * pairs + c1 * c_count + c2] =
                  correlation[back * pairs + c2 * c_count + c1];
            }
          }
        }
      }
    }
  }

  const int taps = window * window * window;
  const Eigen::Index components = static_cast<Eigen::Index>(taps) * channels;
  NeighbourhoodStatistics stats{std::vector<float>(mean.begin(), mean.end()),
                                Eigen::VectorXd(components),
                                Eigen::MatrixXd(components, components)};
  for (int t1 = 0; t1 < taps; ++t1) {
    const std::array<int, 3> p1{t1 % window, (t1 / window) % window, t1 / (window * window)};
    for (int t2 = 0; t2 < taps; ++t2) {
      const std::array<int, 3> p2{t2 % window, (t2 / window) % window, t2 / (window * window)};
      std::array<std::size_t, 3> o{};
      for (std::size_t a = 0; a < 3; ++a) {
        o[a] = offset_index[a][static_cast<std::size_t>(p2[a] - p1[a] + window - 1)];
      }
      const double* r = correlation.data() + combination(o[0], o[1], o[2]) * pairs;
      for (int c1 = 0; c1 < channels; ++c1) {
        for (int c2 = 0; c2 < channels; ++c2) {
          stats.covariance(t1 * channels + c1, t2 * channels + c2) =
              r[static_cast<std::size_t>(c1 * channels + c2)];
        }
      }
    }
    for (int c = 0; c < channels; ++c) {
      stats.mean(t1 * channels + c) = mean[static_cast<std::size_t>(c)];
    }
  }
  return stats;
}

/// Clamped neighbourhoods over a box are not stationary: their covariance is summed as blocked
/// symmetric rank-k products of gathered rows (centred on the channel means), in fixed chunks.
NeighbourhoodStatistics clamped_statistics(const vol::ChannelGrid& level, int window, int spacing,
                                           const Box& box) {
  const int channels = level.channels();
  const std::vector<double> mean = channel_mean(level, box);
  const std::vector<float> centre(mean.begin(), mean.end());
  const ClampedNeighbourhoods sampler(level, window, spacing);
  const int components = window * window * window * channels;
  const std::size_t voxels = box.count();
  const std::size_t blocks = (voxels + kBlockVoxels - 1) / kBlockVoxels;
  const std::size_t chunks = std::min<std::size_t>(kCovarianceChunks, blocks);

  std::vector<Eigen::MatrixXd> chunk_products(chunks);
  std::vector<Eigen::VectorXd> chunk_sums(chunks);
  // OpenBLAS runs on one thread (par::PetscSession sets it), so calling it from our threads
  // does not oversubscribe the cores.
#pragma omp parallel
  {
    RowMatrixF rows(kBlockVoxels, components);
    Eigen::MatrixXf product(components, components);
#pragma omp for schedule(dynamic)
    for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
      Eigen::MatrixXd sum_products = Eigen::MatrixXd::Zero(components, components);
      Eigen::VectorXd sum = Eigen::VectorXd::Zero(components);
      for (std::size_t block = chunk * blocks / chunks; block < (chunk + 1) * blocks / chunks;
           ++block) {
        const std::size_t first = block * kBlockVoxels;
        const std::size_t count = std::min<std::size_t>(kBlockVoxels, voxels - first);
        for (std::size_t r = 0; r < count; ++r) {
          const auto [i, j, k] = box.voxel(first + r);
          sampler.gather(i, j, k, centre, rows.row(static_cast<Eigen::Index>(r)).data());
        }
        // rows^T rows, lower triangle: column-major rows^T is components x count with ld
        // components.
        cblas_ssyrk(CblasColMajor, CblasLower, CblasNoTrans, components, static_cast<int>(count),
                    1.0f, rows.data(), components, 0.0f, product.data(), components);
        for (Eigen::Index col = 0; col < components; ++col) {
          for (Eigen::Index row = col; row < components; ++row) {
            sum_products(row, col) += product(row, col);
          }
        }
        for (std::size_t r = 0; r < count; ++r) {
          const float* row = rows.row(static_cast<Eigen::Index>(r)).data();
          for (Eigen::Index p = 0; p < components; ++p) {
            sum(p) += row[p];
          }
        }
      }
      chunk_products[chunk] = std::move(sum_products);
      chunk_sums[chunk] = std::move(sum);
    }
  }
  Eigen::MatrixXd products = Eigen::MatrixXd::Zero(components, components);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(components);
  for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
    products += chunk_products[chunk];
    sum += chunk_sums[chunk];
  }
  const double inv = 1.0 / static_cast<double>(voxels);
  const Eigen::VectorXd offset = sum * inv; // mean minus the channel means
  NeighbourhoodStatistics stats;
  stats.centre = centre;
  stats.covariance = products * inv - offset * offset.transpose();
  stats.covariance.triangularView<Eigen::StrictlyUpper>() =
      stats.covariance.transpose().triangularView<Eigen::StrictlyUpper>();
  stats.mean = offset;
  for (Eigen::Index p = 0; p < components; ++p) {
    stats.mean(p) += mean[static_cast<std::size_t>(p % channels)];
  }
  return stats;
}

/// The principal axes of a level: the top `dimensions` eigenvectors with variance above the
/// noise floor, sign-fixed; zero columns for the rest.
struct PrincipalAxes {
  Eigen::MatrixXd basis;
  double retained_variance = 0.0;
  bool solved = false;
};

PrincipalAxes principal_axes(const Eigen::MatrixXd& covariance, int dimensions,
                             double noise_floor) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
  PrincipalAxes axes;
  axes.solved = solver.info() == Eigen::Success;
  const Eigen::Index components = covariance.rows();
  axes.basis = Eigen::MatrixXd::Zero(components, dimensions);
  double kept = 0.0;
  for (Eigen::Index q = 0; q < std::min<Eigen::Index>(dimensions, components); ++q) {
    const Eigen::Index e = components - 1 - q; // eigenvalues come in increasing order
    const double variance = solver.eigenvalues()(e);
    if (!(variance > noise_floor)) {
      break;
    }
    Eigen::VectorXd axis = solver.eigenvectors().col(e);
    Eigen::Index largest = 0;
    axis.cwiseAbs().maxCoeff(&largest);
    if (axis(largest) < 0.0) {
      axis = -axis;
    }
    axes.basis.col(q) = axis;
    kept += variance;
  }
  const double total = covariance.trace();
  axes.retained_variance = total > noise_floor ? kept / total : 1.0;
  return axes;
}

/// add_taps on kLanes voxels: the partial sums stay in registers across the taps.
template <std::size_t kLanes>
inline void add_taps_to_lanes(float* out, const float* row, const float* weights, int taps,
                              std::size_t step, std::size_t dimensions, std::size_t q) {
  float sum[kLanes];
  for (std::size_t l = 0; l < kLanes; ++l) {
    sum[l] = out[l];
  }
  for (int t = 0; t < taps; ++t) {
    const float w = weights[static_cast<std::size_t>(t) * dimensions + q];
    const float* in = row + static_cast<std::size_t>(t) * step;
    for (std::size_t l = 0; l < kLanes; ++l) {
      sum[l] += w * in[l];
    }
  }
  for (std::size_t l = 0; l < kLanes; ++l) {
    out[l] = sum[l];
  }
}

/// acc[q * length + i] += sum_t weights[t * dimensions + q] * row[i + t * spacing] for every
/// feature q: the contribution of `taps` taps along x to a row of appearance vectors. Every voxel
/// is summed in the same order, whichever group of lanes it falls in.
__attribute__((target_clones("avx512f", "avx2", "default"))) void
add_taps(float* acc, const float* row, const float* weights, int taps, int spacing,
         std::size_t dimensions, std::size_t length) {
  const auto step = static_cast<std::size_t>(spacing);
  for (std::size_t q = 0; q < dimensions; ++q) {
    float* out = acc + q * length;
    std::size_t i = 0;
    for (; i + 16 <= length; i += 16) {
      add_taps_to_lanes<16>(out + i, row + i, weights, taps, step, dimensions, q);
    }
    for (; i + 4 <= length; i += 4) {
      add_taps_to_lanes<4>(out + i, row + i, weights, taps, step, dimensions, q);
    }
    for (; i < length; ++i) {
      add_taps_to_lanes<1>(out + i, row + i, weights, taps, step, dimensions, q);
    }
  }
}

/// Appearance vectors of the box's voxels in x rows [rows.first, rows.second) (row y + ny z of the
/// box), written into `features` (those rows only, row rows.first first), one x row at a time: (x -
/// mean) B is accumulated from the centred level's rows, padded along x by the taps' reach (wrapped
/// or clamped) so every tap reads them contiguously; only the planes one box plane's taps read are
/// held at a time. Each vector is summed in the same order on any thread and whichever rows are
/// asked for.
void project_level(const vol::ChannelGrid& level, const Box& box, int spacing, bool periodic,
                   const std::vector<float>& centre, const AppearanceLevel& appearance,
                   std::pair<std::ptrdiff_t, std::ptrdiff_t> rows, std::span<float> features) {
  const int window = appearance.window, reach = window / 2 * spacing;
  const int channels = level.channels();
  const auto c_count = static_cast<std::size_t>(channels);
  const auto dimensions = static_cast<std::size_t>(appearance.basis.cols());
  // The basis regrouped by tap row: tap_weights[(g * window + tx) * dimensions + q] with
  // g = (tz * window + ty) * C + c is the weight of tap (tx, ty, tz), channel c in feature q.
  std::vector<float> tap_weights(static_cast<std::size_t>(appearance.basis.size()));
  for (int g = 0; g < window * window * channels; ++g) {
    const int tap_row = g / channels, c = g % channels;
    for (int tx = 0; tx < window; ++tx) {
      const Eigen::Index p = static_cast<Eigen::Index>((tap_row * window + tx) * channels + c);
      for (std::size_t q = 0; q < dimensions; ++q) {
        tap_weights[(static_cast<std::size_t>(g * window + tx)) * dimensions + q] =
            static_cast<float>(appearance.basis(p, static_cast<Eigen::Index>(q)));
      }
    }
  }
  // Features are (x - mean) B = (x - centre) B - (mean - centre) B.
  Eigen::VectorXd centre_tiled(appearance.basis.rows());
  for (Eigen::Index p = 0; p < centre_tiled.size(); ++p) {
    centre_tiled(p) = centre[static_cast<std::size_t>(p) % c_count];
  }
  const Eigen::VectorXf offset =
      (appearance.basis.transpose() * (appearance.mean - centre_tiled)).cast<float>();

  const vol::Dims dims = level.dims();
  const std::array<int, 3> n{dims.nx, dims.ny, dims.nz};
  const auto coordinate = [&](std::size_t axis, int q) {
    return periodic ? vol::ChannelGrid::wrap(q, n[axis]) : vol::ChannelGrid::clamp(q, n[axis]);
  };
  if (rows.second <= rows.first)
    return;
  // One z-plane of the box at a time, from the `window` planes its taps read, centred and padded:
  // padded[c][(tz * ny + y) * width + e] = level(x(e), y, z + (tz - window / 2) spacing)[c] -
  // centre[c], x(e) = lo - reach + e. A coarse level's taps reach far in z and x; padding the
  // planes of all the asked rows at once would hold most of the level, twice as wide.
  const auto ny = static_cast<std::size_t>(n[1]);
  const auto length = static_cast<std::size_t>(box.size[0]);
  const std::size_t width = length + 2 * static_cast<std::size_t>(reach);
  const auto padded_rows = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(window) * ny);
  std::vector<std::vector<float>> padded(
      c_count, std::vector<float>(static_cast<std::size_t>(padded_rows) * width));
  const auto box_rows_per_plane = static_cast<std::ptrdiff_t>(box.size[1]);
  const std::ptrdiff_t first_plane = rows.first / box_rows_per_plane;
  const std::ptrdiff_t last_plane = (rows.second - 1) / box_rows_per_plane;

#pragma omp parallel
  {
    std::vector<float> acc(dimensions * length);
    for (std::ptrdiff_t plane = first_plane; plane <= last_plane; ++plane) {
      const int z = box.lo[2] + static_cast<int>(plane);
#pragma omp for schedule(static)
      for (std::ptrdiff_t row = 0; row < padded_rows; ++row) {
        const auto tz = static_cast<int>(static_cast<std::size_t>(row) / ny);
        const std::size_t row_start =
            level.index(0, static_cast<int>(static_cast<std::size_t>(row) % ny),
                        coordinate(2, z + (tz - window / 2) * spacing));
        for (std::size_t e = 0; e < width; ++e) {
          const auto x =
              static_cast<std::size_t>(coordinate(0, box.lo[0] - reach + static_cast<int>(e)));
          const auto v = level.voxel(row_start + x);
          for (std::size_t c = 0; c < c_count; ++c) {
            padded[c][static_cast<std::size_t>(row) * width + e] = v[c] - centre[c];
          }
        }
      }
      const std::ptrdiff_t plane_rows_end = std::min(rows.second, (plane + 1) * box_rows_per_plane);
#pragma omp for schedule(static)
      for (std::ptrdiff_t row = std::max(rows.first, plane * box_rows_per_plane);
           row < plane_rows_end; ++row) {
        const int y = box.lo[1] + static_cast<int>(row % box_rows_per_plane);
        std::fill(acc.begin(), acc.end(), 0.0f);
        for (int tz = 0; tz < window; ++tz) {
          for (int ty = 0; ty < window; ++ty) {
            const auto sy =
                static_cast<std::size_t>(coordinate(1, y + (ty - window / 2) * spacing));
            const std::size_t source_row = static_cast<std::size_t>(tz) * ny + sy;
            for (std::size_t c = 0; c < c_count; ++c) {
              const auto g = static_cast<std::size_t>((tz * window + ty) * channels) + c;
              add_taps(acc.data(), padded[c].data() + source_row * width,
                       tap_weights.data() + g * static_cast<std::size_t>(window) * dimensions,
                       window, spacing, dimensions, length);
            }
          }
        }
        float* row_out =
            features.data() + static_cast<std::size_t>(row - rows.first) * length * dimensions;
        for (std::size_t i = 0; i < length; ++i) {
          float* out = row_out + i * dimensions;
          for (std::size_t q = 0; q < dimensions; ++q) {
            out[q] = acc[q * length + i] - offset(static_cast<Eigen::Index>(q));
          }
        }
      }
    }
  }
}

/// Planes [z_begin, z_end) of `grid` cropped to `box`, into `out`.
void crop_planes(const vol::ChannelGrid& grid, const Box& box, int z_begin, int z_end,
                 std::span<float> out) {
  const auto channels = static_cast<std::size_t>(grid.channels());
  const auto row = static_cast<std::size_t>(box.size[0]) * channels;
  std::size_t at = 0;
  for (int k = z_begin; k < z_end; ++k) {
    for (int j = 0; j < box.size[1]; ++j, at += row) {
      const auto in =
          grid.data().subspan(grid.index(box.lo[0], box.lo[1] + j, box.lo[2] + k) * channels, row);
      std::copy(in.begin(), in.end(), out.begin() + static_cast<std::ptrdiff_t>(at));
    }
  }
}

/// `grid` cropped to `box`, held once per node.
vol::ChannelGrid node_shared_crop(const std::shared_ptr<const par::NodeLayout>& layout,
                                  const vol::ChannelGrid& grid, const Box& box) {
  return vol::node_shared_grid(layout, vol::Dims{box.size[0], box.size[1], box.size[2]},
                               grid.channels(), [&](int z_begin, int z_end, std::span<float> out) {
                                 crop_planes(grid, box, z_begin, z_end, out);
                               });
}

/// The Gaussian stack of `exemplar` (vol::gaussian_stack, the same bytes), every level held once
/// per node: the node's ranks blur a share of each level's planes.
std::vector<vol::ChannelGrid>
node_shared_gaussian_stack(const std::shared_ptr<const par::NodeLayout>& layout,
                           const vol::ChannelGrid& exemplar, bool periodic) {
  const vol::Dims dims = exemplar.dims();
  const Box whole{{0, 0, 0}, {dims.nx, dims.ny, dims.nz}};
  const int coarsest = vol::coarsest_stack_level(dims);
  std::vector<vol::ChannelGrid> stack;
  stack.reserve(static_cast<std::size_t>(coarsest) + 1);
  // An exemplar already held once per node (load_exemplar_once_per_node, on the same ranks'
  // nodes) is level 0 itself.
  stack.push_back(exemplar.node_shared() ? exemplar : node_shared_crop(layout, exemplar, whole));
  for (int s = 0; s < coarsest; ++s) {
    const vol::ChannelGrid& finer = stack.back();
    stack.push_back(vol::node_shared_grid(
        layout, dims, exemplar.channels(), [&](int z_begin, int z_end, std::span<float> out) {
          vol::binomial_blur_3d_planes(finer, 1 << s, periodic, z_begin, z_end, out);
        }));
  }
  return stack;
}

} // namespace

AppearanceSpace build_appearance_space(const par::Comm& comm, const vol::ChannelGrid& exemplar,
                                       const AppearanceOptions& options) {
  const int window = options.window;
  const int channels = exemplar.channels();
  TEXSIM_VERIFY(window >= 1 && window % 2 == 1, "appearance window must be odd, got " << window);
  const int components = window * window * window * channels;
  TEXSIM_VERIFY(options.dimensions >= 1,
                "appearance dimensions must be positive, got " << options.dimensions);
  const vol::Dims dims = exemplar.dims();
  TEXSIM_VERIFY(std::min({dims.nx, dims.ny, dims.nz}) >= window,
                "exemplar " << dims.nx << " x " << dims.ny << " x " << dims.nz
                            << " is smaller than the appearance window " << window);
  const bool periodic = options.border == ExemplarBorder::toroidal;
  const int cut = periodic ? 0 : window / 2;
  const Box box{{cut, cut, cut}, {dims.nx - 2 * cut, dims.ny - 2 * cut, dims.nz - 2 * cut}};
  const std::size_t feature_values = box.count() * static_cast<std::size_t>(options.dimensions);
  TEXSIM_VERIFY(feature_values <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
                "exemplar of " << box.count() << " voxels: its " << options.dimensions
                               << "-dimensional features exceed one MPI message");

  float largest = 0.0f;
  for (const float v : exemplar.data()) {
    largest = std::max(largest, std::abs(v));
  }
  const double noise_floor =
      components * std::pow(kRoundingUlps * FLT_EPSILON * static_cast<double>(largest), 2);

  const auto layout = par::NodeLayout::make(comm);
  const std::vector<vol::ChannelGrid> stack =
      node_shared_gaussian_stack(layout, exemplar, periodic);
  const std::size_t level_count = stack.size();
  AppearanceSpace space;
  space.periodic = periodic;
  space.levels.resize(level_count);
  std::vector<std::vector<float>> centres(level_count, std::vector<float>(channels));
  // The statistics and principal axes of level s are computed by rank s mod size alone, then
  // shared: the same axes for any rank count.
  for (std::size_t s = 0; s < level_count; ++s) {
    AppearanceLevel& level = space.levels[s];
    level.spacing = 1 << s;
    level.window = window;
    level.mean = Eigen::VectorXd::Zero(components);
    level.basis = Eigen::MatrixXd::Zero(components, options.dimensions);
    if (static_cast<int>(s % static_cast<std::size_t>(comm.size)) != comm.rank)
      continue;
    NeighbourhoodStatistics statistics =
        periodic ? toroidal_statistics(stack[s], window, level.spacing)
                 : clamped_statistics(stack[s], window, level.spacing, box);
    const PrincipalAxes axes =
        principal_axes(statistics.covariance, options.dimensions, noise_floor);
    // A failed decomposition travels as NaN variance, so every rank reports it.
    level.retained_variance = axes.solved ? axes.retained_variance : std::nan("");
    level.mean = std::move(statistics.mean);
    level.basis = axes.basis;
    centres[s] = std::move(statistics.centre);
  }
  for (std::size_t s = 0; s < level_count && comm.size > 1; ++s) {
    AppearanceLevel& level = space.levels[s];
    const int owner = static_cast<int>(s % static_cast<std::size_t>(comm.size));
    MPI_Bcast(level.mean.data(), components, MPI_DOUBLE, owner, comm.raw);
    MPI_Bcast(level.basis.data(), static_cast<int>(level.basis.size()), MPI_DOUBLE, owner,
              comm.raw);
    MPI_Bcast(&level.retained_variance, 1, MPI_DOUBLE, owner, comm.raw);
    MPI_Bcast(centres[s].data(), channels, MPI_FLOAT, owner, comm.raw);
  }
  for (std::size_t s = 0; s < level_count; ++s)
    TEXSIM_VERIFY(!std::isnan(space.levels[s].retained_variance),
                  "eigen decomposition of the level " << s << " covariance failed");

  // Every rank projects an even share of the x rows of each level; the shares are then
  // concatenated once per node, which all of the node's ranks read.
  const auto rows = static_cast<std::ptrdiff_t>(box.size[1]) * box.size[2];
  const auto row_of_rank = [&](int r) { return rows * r / comm.size; };
  const std::pair<std::ptrdiff_t, std::ptrdiff_t> my_rows{row_of_rank(comm.rank),
                                                          row_of_rank(comm.rank + 1)};
  const vol::Dims box_dims{box.size[0], box.size[1], box.size[2]};
  for (std::size_t s = 0; s < level_count; ++s) {
    AppearanceLevel& level = space.levels[s];
    std::vector<float> my_features(static_cast<std::size_t>(my_rows.second - my_rows.first) *
                                   static_cast<std::size_t>(box.size[0]) *
                                   static_cast<std::size_t>(options.dimensions));
    project_level(stack[s], box, level.spacing, periodic, centres[s], level, my_rows, my_features);
    level.features =
        vol::ChannelGrid(box_dims, options.dimensions,
                         par::NodeSharedArray<float>::concatenate(layout, my_features));
  }
  for (const vol::ChannelGrid& level : stack)
    space.stack.push_back(periodic ? level : node_shared_crop(layout, level, box));
  space.colours = space.stack.front(); // stack level 0 is the working exemplar
  return space;
}

AppearanceSpace build_appearance_space(const vol::ChannelGrid& exemplar,
                                       const AppearanceOptions& options) {
  return build_appearance_space(par::Comm{MPI_COMM_SELF, 0, 1}, exemplar, options);
}

void project_neighbourhood(const AppearanceLevel& level, const vol::ChannelGrid& colours, int i,
                           int j, int k, std::span<float> out) {
  const int window = level.window, channels = colours.channels(), reach = window / 2;
  TEXSIM_VERIFY(level.basis.rows() ==
                        static_cast<Eigen::Index>(window) * window * window * channels &&
                    out.size() == static_cast<std::size_t>(level.basis.cols()),
                "project_neighbourhood: " << channels << " channels and " << out.size()
                                          << " outputs do not fit a basis of " << level.basis.rows()
                                          << " x " << level.basis.cols());
  Eigen::VectorXd centred(level.basis.rows());
  Eigen::Index p = 0;
  for (int dz = -reach; dz <= reach; ++dz) {
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        const auto v = colours.voxel(colours.periodic_index(i + dx, j + dy, k + dz));
        for (int c = 0; c < channels; ++c, ++p) {
          centred(p) = v[static_cast<std::size_t>(c)] - level.mean(p);
        }
      }
    }
  }
  const Eigen::VectorXd projected = level.basis.transpose() * centred;
  for (std::size_t q = 0; q < out.size(); ++q) {
    out[q] = static_cast<float>(projected(static_cast<Eigen::Index>(q)));
  }
}

} // namespace texsim::pipelines::solid_synthesis
