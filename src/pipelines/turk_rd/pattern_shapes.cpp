#include "pipelines/turk_rd/pattern_shapes.hpp"

#include "par/reproducible_sum.hpp"
#include "pipelines/turk_rd/region_moments.hpp"

#include <Eigen/Eigenvalues>

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace texsim::pipelines::turk_rd {
namespace {

/// sqrt(lambda1 / lambda2) of the covariance of a region's cells (0 if degenerate).
double principal_aspect(const RegionMoments& region) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance_of(region),
                                                              Eigen::EigenvaluesOnly);
  const Eigen::Vector3d lambda = solver.eigenvalues(); // increasing
  return lambda[1] > 0 ? std::sqrt(lambda[2] / lambda[1]) : 0.0;
}

} // namespace

PatternShapes measure_pattern(const par::Comm& comm, const geom::SurfaceCells& cells,
                              std::span<const double> owned_values) {
  const std::int32_t owned = cells.owned_count();
  std::int64_t total_cells = owned;
  MPI_Allreduce(MPI_IN_PLACE, &total_cells, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  if (total_cells == 0)
    return {};
  // The mean as a reproducible sum: the same threshold, to the bit, on any number of ranks.
  const double mean = par::reproducible_sum(comm, owned_values) / double(total_cells);
  std::vector<char> above(std::size_t(owned), 0);
  for (std::int32_t i = 0; i < owned; ++i)
    above[std::size_t(i)] = owned_values[std::size_t(i)] > mean;
  const auto labels = label_cell_regions(comm, cells, above);
  const auto regions = region_moments_on_root(comm, cells, labels);

  double result[7] = {0, 0, 0, 0, 0, 0, 0};
  if (comm.is_root()) {
    std::vector<double> elongation, aspect;
    double weighted_sum = 0, weight = 0, weighted_aspect_sum = 0;
    std::int64_t above_cells = 0;
    for (const RegionMoments& region : regions) {
      above_cells += region.cells;
      if (region.cells < 4)
        continue;
      elongation.push_back(region.perimeter * region.perimeter /
                           (4.0 * std::numbers::pi * region.area));
      weighted_sum += double(region.cells) * elongation.back();
      weight += double(region.cells);
      aspect.push_back(principal_aspect(region));
      weighted_aspect_sum += double(region.cells) * aspect.back();
    }
    std::sort(elongation.begin(), elongation.end());
    std::sort(aspect.begin(), aspect.end());
    const double count = double(regions.size());
    result[0] = count;
    result[1] = regions.empty() ? 0.0 : double(above_cells) / count;
    result[2] = elongation.empty() ? 0.0 : elongation[elongation.size() / 2];
    result[3] = elongation.empty() ? 0.0 : elongation.back();
    result[4] = weight > 0 ? weighted_sum / weight : 0.0;
    result[5] = aspect.empty() ? 0.0 : aspect[aspect.size() / 2];
    result[6] = weight > 0 ? weighted_aspect_sum / weight : 0.0;
  }
  MPI_Bcast(result, 7, MPI_DOUBLE, 0, comm.raw);
  return {int(result[0]), result[1], result[2], result[3], result[4], result[5], result[6]};
}

} // namespace texsim::pipelines::turk_rd
