#include "pipelines/turk_rd/ring_profile.hpp"

#include "par/gather_to_root.hpp"
#include "par/reproducible_sum.hpp"
#include "pipelines/turk_rd/region_moments.hpp"

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

/// The region's table entry from its summed moments.
RingRegion describe(const RegionMoments& region) {
  const Eigen::Vector3d mean = centre_of(region);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance_of(region));
  const Eigen::Vector3d a1 = solver.eigenvectors().col(2);
  const Eigen::Vector3d a2 = solver.eigenvectors().col(1);
  return {region.label,
          {mean[0], mean[1], mean[2]},
          std::sqrt(region.area / std::numbers::pi),
          {a1[0], a1[1], a1[2]},
          {a2[0], a2[1], a2[2]}};
}

/// The regions of at least kRingMinCells cells, on every rank. Collective.
std::vector<RingRegion> measured_regions(const par::Comm& comm, const geom::SurfaceCells& cells,
                                         std::span<const std::int64_t> labels) {
  std::vector<RingRegion> table;
  for (const RegionMoments& region : region_moments_on_root(comm, cells, labels))
    if (region.cells >= kRingMinCells && region.area > 0)
      table.push_back(describe(region));
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
  const par::SliceGrids area_grids = par::slice_grids_for(comm, areas);
  const std::vector<RingRegion> table = measured_regions(comm, cells, labels);
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
        const int sector = std::clamp(
            int((angle + std::numbers::pi) / (2 * std::numbers::pi) * kSectors), 0, kSectors - 1);
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
