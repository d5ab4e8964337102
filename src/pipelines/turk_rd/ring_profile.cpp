#include "pipelines/turk_rd/ring_profile.hpp"

#include "par/gather_to_root.hpp"
#include "par/reproducible_sum.hpp"
#include "pipelines/turk_rd/pattern_shapes.hpp"

#include <Eigen/Eigenvalues>

#include <mpi.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <unordered_map>
#include <vector>

namespace texsim::pipelines::turk_rd {
namespace {

/// One rank's share of a region's cell count, area, and area-weighted first (x, y, z) and second
/// (xx, xy, xz, yy, yz, zz) moments of the cells' positions.
struct RegionShare {
  std::int64_t label = 0;
  std::int64_t cells = 0;
  par::FoldedSum area{};
  std::array<par::FoldedSum, 3> first{};
  std::array<par::FoldedSum, 6> second{};
};

/// A measured region: its centre, equivalent radius and a frame of its tangent plane (the
/// principal axes of its cells' positions; the third, the normal, is the least spread).
struct RingRegion {
  std::int64_t label = 0;
  double centre[3] = {0, 0, 0};
  double radius = 0;
  double axis1[3] = {0, 0, 0};
  double axis2[3] = {0, 0, 0};
};

/// The angular sectors of a region's rim that hold a mark, as bits; ORed over ranks.
struct SectorShare {
  std::int64_t label = 0;
  std::uint32_t sectors = 0;
};

constexpr int kSectors = 8;

std::array<double, 6> second_moments(double area, const geom::Vec3& x) {
  return {area * x[0] * x[0], area * x[0] * x[1], area * x[0] * x[2],
          area * x[1] * x[1], area * x[1] * x[2], area * x[2] * x[2]};
}

/// The region's table entry from its summed moments.
RingRegion describe(std::int64_t label, double area, const std::array<double, 3>& first,
                    const std::array<double, 6>& second) {
  const Eigen::Vector3d mean(first[0] / area, first[1] / area, first[2] / area);
  Eigen::Matrix3d covariance;
  covariance << second[0], second[1], second[2], second[1], second[3], second[4], second[2],
      second[4], second[5];
  covariance = covariance / area - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Eigen::Vector3d a1 = solver.eigenvectors().col(2);
  const Eigen::Vector3d a2 = solver.eigenvectors().col(1);
  return {label, {mean[0], mean[1], mean[2]}, std::sqrt(area / std::numbers::pi),
          {a1[0], a1[1], a1[2]}, {a2[0], a2[1], a2[2]}};
}

/// Rank 0 adds the shares region by region and keeps the regions of at least kRingMinCells cells;
/// every rank gets that table. Collective.
std::vector<RingRegion> measured_regions(const par::Comm& comm,
                                         const std::vector<RegionShare>& shares) {
  const auto gathered = par::gather_to_root(comm, std::span<const RegionShare>(shares));
  std::vector<RingRegion> table;
  if (comm.is_root()) {
    std::vector<RegionShare> sorted = gathered;
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const RegionShare& a, const RegionShare& b) { return a.label < b.label; });
    std::vector<RegionShare> regions;
    for (const RegionShare& share : sorted) {
      if (regions.empty() || regions.back().label != share.label) {
        regions.push_back(share);
        continue;
      }
      RegionShare& region = regions.back();
      region.cells += share.cells;
      for (std::size_t k = 0; k < share.area.size(); ++k) {
        region.area[k] += share.area[k];
        for (int c = 0; c < 3; ++c)
          region.first[c][k] += share.first[c][k];
        for (int c = 0; c < 6; ++c)
          region.second[c][k] += share.second[c][k];
      }
    }
    for (const RegionShare& region : regions) {
      const double area = par::SliceGrids::total(region.area);
      if (region.cells < kRingMinCells || !(area > 0))
        continue;
      std::array<double, 3> first{};
      std::array<double, 6> second{};
      for (int c = 0; c < 3; ++c)
        first[c] = par::SliceGrids::total(region.first[c]);
      for (int c = 0; c < 6; ++c)
        second[c] = par::SliceGrids::total(region.second[c]);
      table.push_back(describe(region.label, area, first, second));
    }
  }
  std::int64_t count = std::int64_t(table.size());
  MPI_Bcast(&count, 1, MPI_INT64_T, 0, comm.raw);
  table.resize(std::size_t(count));
  MPI_Bcast(table.data(), int(count * std::int64_t(sizeof(RingRegion))), MPI_BYTE, 0, comm.raw);
  return table;
}

/// The mean over the `regions` measured regions of the fraction of their rim's sectors holding a
/// mark (each rank's sectors ORed by region on rank 0). Collective.
double rim_sector_fraction(const par::Comm& comm,
                           const std::unordered_map<std::int64_t, std::uint32_t>& sectors_of,
                           std::size_t regions) {
  std::vector<SectorShare> mine;
  for (const auto& [label, sectors] : sectors_of)
    mine.push_back({label, sectors});
  const auto gathered = par::gather_to_root(comm, std::span<const SectorShare>(mine));
  double fraction = 0;
  if (comm.is_root() && regions > 0) {
    std::unordered_map<std::int64_t, std::uint32_t> merged;
    for (const SectorShare& share : gathered)
      merged[share.label] |= share.sectors;
    long long marked_sectors = 0; // integers: the same sum in any order
    for (const auto& entry : merged)
      marked_sectors += std::popcount(entry.second);
    fraction = double(marked_sectors) / double(kSectors * regions);
  }
  MPI_Bcast(&fraction, 1, MPI_DOUBLE, 0, comm.raw);
  return fraction;
}

} // namespace

RingProfile measure_rings(const par::Comm& comm, const geom::SurfaceCells& cells,
                          std::span<const char> in_region, std::span<const char> marked) {
  const std::int32_t owned = cells.owned_count();
  const auto labels = label_cell_regions(comm, cells, in_region);
  const auto areas = cells.areas();
  std::vector<double> firsts, seconds;
  firsts.reserve(3 * std::size_t(owned));
  seconds.reserve(6 * std::size_t(owned));
  for (std::int32_t i = 0; i < owned; ++i) {
    const geom::Vec3& x = cells.points()[i].position;
    for (int c = 0; c < 3; ++c)
      firsts.push_back(areas[i] * x[c]);
    const auto second = second_moments(areas[i], x);
    seconds.insert(seconds.end(), second.begin(), second.end());
  }
  const par::SliceGrids area_grids = par::slice_grids_for(comm, areas);
  const par::SliceGrids first_grids = par::slice_grids_for(comm, firsts);
  const par::SliceGrids second_grids = par::slice_grids_for(comm, seconds);

  std::vector<RegionShare> shares;
  {
    std::unordered_map<std::int64_t, std::size_t> share_of;
    for (std::int32_t i = 0; i < owned; ++i) {
      if (labels[i] < 0)
        continue;
      const auto [at, added] = share_of.try_emplace(labels[i], shares.size());
      if (added)
        shares.push_back({labels[i], 0, {}, {}, {}});
      RegionShare& share = shares[at->second];
      ++share.cells;
      area_grids.add(areas[i], share.area);
      for (int c = 0; c < 3; ++c)
        first_grids.add(firsts[3 * std::size_t(i) + std::size_t(c)], share.first[c]);
      for (int c = 0; c < 6; ++c)
        second_grids.add(seconds[6 * std::size_t(i) + std::size_t(c)], share.second[c]);
    }
  }
  const std::vector<RingRegion> table = measured_regions(comm, shares);
  std::unordered_map<std::int64_t, const RingRegion*> region_of;
  for (const RingRegion& region : table)
    region_of[region.label] = &region;

  // Area and marked area per distance bin, and the centre and rim ranges.
  std::array<par::FoldedSum, kRingBins> bin_area{}, bin_marked{};
  par::FoldedSum centre_area{}, centre_marked{}, rim_area{}, rim_marked{};
  std::unordered_map<std::int64_t, std::uint32_t> sectors_of;
  for (std::int32_t i = 0; i < owned; ++i) {
    const auto found = labels[i] < 0 ? region_of.end() : region_of.find(labels[i]);
    if (found == region_of.end())
      continue;
    const RingRegion& region = *found->second;
    const geom::Vec3& x = cells.points()[i].position;
    const geom::Vec3 centre(region.centre[0], region.centre[1], region.centre[2]);
    const double r = (x - centre).norm() / region.radius;
    const int bin = std::min(int(r / 0.25), kRingBins - 1);
    area_grids.add(areas[i], bin_area[bin]);
    if (marked[i])
      area_grids.add(areas[i], bin_marked[bin]);
    if (r < 0.5) {
      area_grids.add(areas[i], centre_area);
      if (marked[i])
        area_grids.add(areas[i], centre_marked);
    } else if (r >= 0.75 && r < 1.25) {
      area_grids.add(areas[i], rim_area);
      if (marked[i]) {
        area_grids.add(areas[i], rim_marked);
        const geom::Vec3 d = x - centre;
        const double angle =
            std::atan2(d.dot(geom::Vec3(region.axis2[0], region.axis2[1], region.axis2[2])),
                       d.dot(geom::Vec3(region.axis1[0], region.axis1[1], region.axis1[2])));
        const int sector =
            std::clamp(int((angle + std::numbers::pi) / (2 * std::numbers::pi) * kSectors), 0,
                       kSectors - 1);
        sectors_of[region.label] |= 1u << sector;
      }
    }
  }
  const auto fraction = [&](const par::FoldedSum& part, const par::FoldedSum& whole) {
    const double total = par::SliceGrids::total(par::sum_over_ranks(comm, whole));
    const double covered = par::SliceGrids::total(par::sum_over_ranks(comm, part));
    return total > 0 ? covered / total : 0.0;
  };
  RingProfile profile;
  profile.regions = int(table.size());
  for (int b = 0; b < kRingBins; ++b)
    profile.marked_by_radius[b] = fraction(bin_marked[b], bin_area[b]);
  profile.centre_marked = fraction(centre_marked, centre_area);
  profile.rim_marked = fraction(rim_marked, rim_area);
  profile.rim_sectors_marked = rim_sector_fraction(comm, sectors_of, table.size());
  return profile;
}

} // namespace texsim::pipelines::turk_rd
