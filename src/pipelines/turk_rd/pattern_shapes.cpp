#include "pipelines/turk_rd/pattern_shapes.hpp"

#include "geom/distributed_regions.hpp"
#include "par/gather_to_root.hpp"
#include "par/ghosted_vector.hpp"
#include "par/reproducible_sum.hpp"

#include <Eigen/Eigenvalues>

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace texsim::pipelines::turk_rd {
namespace {

/// One rank's share of one region: its cells there, and their area and border with other cells
/// as sliced partial sums (added across ranks exactly).
struct RegionShare {
  std::int64_t label = 0;
  std::int64_t cells = 0;
  par::FoldedSum area{};
  par::FoldedSum perimeter{};
  /// Area-weighted first moments (x, y, z) and second moments (xx, xy, xz, yy, yz, zz).
  std::array<par::FoldedSum, 3> first{};
  std::array<par::FoldedSum, 6> second{};
};

/// The products a x_c and a x_c x_d of a cell's area a and position x that the moments add.
struct CellMoments {
  std::array<double, 3> first;
  std::array<double, 6> second;
};

CellMoments moments_of(double area, const geom::Vec3& x) {
  return {{area * x[0], area * x[1], area * x[2]},
          {area * x[0] * x[0], area * x[0] * x[1], area * x[0] * x[2], area * x[1] * x[1],
           area * x[1] * x[2], area * x[2] * x[2]}};
}

/// sqrt(lambda1 / lambda2) of the covariance from the summed area and moments (0 if degenerate).
double principal_aspect(double area, const std::array<double, 3>& first,
                        const std::array<double, 6>& second) {
  const Eigen::Vector3d mean(first[0] / area, first[1] / area, first[2] / area);
  Eigen::Matrix3d covariance;
  covariance << second[0], second[1], second[2], second[1], second[3], second[4], second[2],
      second[4], second[5];
  covariance = covariance / area - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d lambda = solver.eigenvalues(); // increasing
  return lambda[1] > 0 ? std::sqrt(lambda[2] / lambda[1]) : 0.0;
}

/// The cell graph on this rank's owned cells and ghosts, symmetric: the ghosts' rows hold the owned
/// cells next to them, so two owned cells joined only through a ghost share a local component.
geom::CsrAdjacency local_graph(const geom::SurfaceCells& cells) {
  const auto& stencil = cells.neighbors();
  const std::int32_t owned = cells.owned_count();
  const auto nodes = std::size_t(owned) + cells.ghost_ids().size();
  geom::CsrAdjacency graph;
  graph.offsets.assign(nodes + 1, 0);
  for (std::int32_t i = 0; i < owned; ++i) {
    graph.offsets[i + 1] += stencil.offsets[i + 1] - stencil.offsets[i];
    for (const std::int32_t j : stencil.row(i))
      if (j >= owned)
        ++graph.offsets[j + 1];
  }
  for (std::size_t v = 0; v < nodes; ++v)
    graph.offsets[v + 1] += graph.offsets[v];
  graph.indices.resize(std::size_t(graph.offsets.back()));
  std::vector<std::int64_t> next(graph.offsets.begin(), graph.offsets.end() - 1);
  for (std::int32_t i = 0; i < owned; ++i)
    for (const std::int32_t j : stencil.row(i)) {
      graph.indices[next[i]++] = j;
      if (j >= owned)
        graph.indices[next[j]++] = i;
    }
  return graph;
}

} // namespace

std::vector<std::int64_t> label_cell_regions(const par::Comm& comm, const geom::SurfaceCells& cells,
                                             std::span<const char> owned_marked) {
  const std::int32_t owned = cells.owned_count();
  par::GhostedVector halo(comm, owned, cells.ghost_blocks());
  std::vector<double> marks(owned_marked.begin(), owned_marked.end());
  halo.set_owned(marks);
  const std::span<const double> local_marks = halo.local();
  std::vector<char> marked(local_marks.size());
  std::vector<std::int64_t> ids(local_marks.size());
  for (std::size_t i = 0; i < local_marks.size(); ++i) {
    marked[i] = local_marks[i] != 0;
    ids[i] = i < std::size_t(owned) ? cells.ids()[i] : cells.ghost_ids()[i - std::size_t(owned)];
  }
  return geom::label_regions_across_ranks(
      comm, local_graph(cells), marked, ids, owned, [&](std::span<double> local) {
        halo.set_owned(local.first(std::size_t(owned)));
        std::copy(halo.local().begin() + owned, halo.local().end(), local.begin() + owned);
      });
}

PatternShapes measure_pattern(const par::Comm& comm, const geom::SurfaceCells& cells,
                              std::span<const double> owned_values) {
  const std::int32_t owned = cells.owned_count();
  const auto& stencil = cells.neighbors();
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

  // Border lengths as the old serial measure had them: coupling x distance between the cells.
  const auto position = [&](std::int32_t local) {
    return local < owned ? cells.points()[local].position : cells.ghost_positions()[local - owned];
  };
  std::vector<double> borders(stencil.indices.size());
  for (std::int32_t i = 0; i < owned; ++i)
    for (std::int64_t e = stencil.offsets[i]; e < stencil.offsets[i + 1]; ++e)
      borders[e] = cells.couplings()[e] * (position(i) - position(stencil.indices[e])).norm();
  const par::SliceGrids area_grids = par::slice_grids_for(comm, cells.areas());
  const par::SliceGrids border_grids = par::slice_grids_for(comm, borders);
  std::vector<double> firsts, seconds;
  firsts.reserve(3 * std::size_t(owned));
  seconds.reserve(6 * std::size_t(owned));
  for (std::int32_t i = 0; i < owned; ++i) {
    const CellMoments m = moments_of(cells.areas()[i], position(i));
    firsts.insert(firsts.end(), m.first.begin(), m.first.end());
    seconds.insert(seconds.end(), m.second.begin(), m.second.end());
  }
  const par::SliceGrids first_grids = par::slice_grids_for(comm, firsts);
  const par::SliceGrids second_grids = par::slice_grids_for(comm, seconds);

  // This rank's share of each region (in first-seen order: the sums are exact, so the order in
  // which cells are added does not matter).
  std::vector<RegionShare> shares;
  {
    std::unordered_map<std::int64_t, std::size_t> share_of;
    for (std::int32_t i = 0; i < owned; ++i) {
      if (labels[i] < 0)
        continue;
      const auto [at, added] = share_of.try_emplace(labels[i], shares.size());
      if (added)
        shares.push_back({labels[i], 0, {}, {}, {}, {}});
      RegionShare& share = shares[at->second];
      ++share.cells;
      area_grids.add(cells.areas()[i], share.area);
      for (int c = 0; c < 3; ++c)
        first_grids.add(firsts[3 * std::size_t(i) + std::size_t(c)], share.first[c]);
      for (int c = 0; c < 6; ++c)
        second_grids.add(seconds[6 * std::size_t(i) + std::size_t(c)], share.second[c]);
      for (std::int64_t e = stencil.offsets[i]; e < stencil.offsets[i + 1]; ++e)
        if (labels[stencil.indices[e]] != labels[i])
          border_grids.add(borders[e], share.perimeter);
    }
  }
  // Rank 0 adds the shares region by region (O(regions) data, not O(cells)).
  const auto gathered = par::gather_to_root(comm, std::span<const RegionShare>(shares));
  double result[7] = {0, 0, 0, 0, 0, 0, 0};
  if (comm.is_root()) {
    std::vector<RegionShare> regions;
    std::vector<RegionShare> sorted = gathered;
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const RegionShare& a, const RegionShare& b) { return a.label < b.label; });
    for (const RegionShare& share : sorted) {
      if (regions.empty() || regions.back().label != share.label) {
        regions.push_back(share);
        continue;
      }
      RegionShare& region = regions.back();
      region.cells += share.cells;
      for (std::size_t k = 0; k < share.area.size(); ++k) {
        region.area[k] += share.area[k];
        region.perimeter[k] += share.perimeter[k];
        for (int c = 0; c < 3; ++c)
          region.first[c][k] += share.first[c][k];
        for (int c = 0; c < 6; ++c)
          region.second[c][k] += share.second[c][k];
      }
    }
    std::vector<double> elongation, aspect;
    double weighted_sum = 0, weight = 0, weighted_aspect_sum = 0;
    std::int64_t above_cells = 0;
    for (const RegionShare& region : regions) {
      above_cells += region.cells;
      if (region.cells < 4)
        continue;
      const double perimeter = par::SliceGrids::total(region.perimeter);
      elongation.push_back(perimeter * perimeter /
                           (4.0 * std::numbers::pi * par::SliceGrids::total(region.area)));
      weighted_sum += double(region.cells) * elongation.back();
      weight += double(region.cells);
      std::array<double, 3> first{};
      std::array<double, 6> second{};
      for (int c = 0; c < 3; ++c)
        first[c] = par::SliceGrids::total(region.first[c]);
      for (int c = 0; c < 6; ++c)
        second[c] = par::SliceGrids::total(region.second[c]);
      aspect.push_back(principal_aspect(par::SliceGrids::total(region.area), first, second));
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
