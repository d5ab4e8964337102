#include "pipelines/solid_synthesis/synthesis_coherence.hpp"

#include "vol/channel_grid.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

double incoherent_fraction(const par::Comm& comm, const CoordinateSlab& slab,
                           const LevelJacobians* jacobians, const vol::Dims& exemplar,
                           const std::array<int, 3>& crop) {
  const LevelLayout& layout = slab.layout();
  const auto same = [&](const Coord& a, const Coord& b) {
    return vol::ChannelGrid::wrap(a.x - b.x, exemplar.nx) == 0 &&
           vol::ChannelGrid::wrap(a.y - b.y, exemplar.ny) == 0 &&
           vol::ChannelGrid::wrap(a.z - b.z, exemplar.nz) == 0;
  };
  const auto rounded = [](float v) { return static_cast<std::int32_t>(std::floor(v + 0.5f)); };
  const bool counts = !layout.replicated || comm.is_root();
  const int z_end = counts ? std::min(layout.z_end, crop[2]) : layout.z_begin;
  std::int64_t incoherent = 0, voxels = 0;
#pragma omp parallel for schedule(static) reduction(+ : incoherent, voxels)
  for (int k = layout.z_begin; k < z_end; ++k)
    for (int j = 0; j < crop[1]; ++j)
      for (int i = 0; i < crop[0]; ++i) {
        const Coord s = slab.at(i, j, k);
        bool continued = false;
        for (int axis = 0; axis < 3 && !continued; ++axis)
          for (const int sign : {-1, 1}) {
            Coord step{0, 0, 0};
            if (jacobians) {
              const auto column = jacobians->a(i, j, k).col(axis) * float(sign);
              step = {rounded(column.x()), rounded(column.y()), rounded(column.z())};
            } else {
              (axis == 0 ? step.x : axis == 1 ? step.y : step.z) = sign;
            }
            const Coord neighbour = slab.at(i + (axis == 0 ? sign : 0), j + (axis == 1 ? sign : 0),
                                            k + (axis == 2 ? sign : 0));
            if (same(neighbour, s + step)) {
              continued = true;
              break;
            }
          }
        incoherent += continued ? 0 : 1;
        ++voxels;
      }
  std::int64_t totals[2] = {incoherent, voxels};
  MPI_Allreduce(MPI_IN_PLACE, totals, 2, MPI_INT64_T, MPI_SUM, comm.raw);
  return totals[1] > 0 ? double(totals[0]) / double(totals[1]) : 0.0;
}

double largest_offset_share(const par::Comm& comm, const CoordinateSlab& slab,
                            const vol::Dims& exemplar, const std::array<int, 3>& crop) {
  const LevelLayout& layout = slab.layout();
  const bool counts = !layout.replicated || comm.is_root();
  const int z_end = counts ? std::min(layout.z_end, crop[2]) : layout.z_begin;
  std::vector<std::int64_t> voxels_per_offset(std::size_t(exemplar.nx) * exemplar.ny * exemplar.nz);
  for (int k = layout.z_begin; k < z_end; ++k)
    for (int j = 0; j < crop[1]; ++j)
      for (int i = 0; i < crop[0]; ++i) {
        const Coord s = slab.at(i, j, k);
        const std::size_t offset =
            (std::size_t(vol::ChannelGrid::wrap(s.z - k, exemplar.nz)) * exemplar.ny +
             std::size_t(vol::ChannelGrid::wrap(s.y - j, exemplar.ny))) *
                exemplar.nx +
            std::size_t(vol::ChannelGrid::wrap(s.x - i, exemplar.nx));
        ++voxels_per_offset[offset];
      }
  MPI_Allreduce(MPI_IN_PLACE, voxels_per_offset.data(), int(voxels_per_offset.size()), MPI_INT64_T,
                MPI_SUM, comm.raw);
  std::int64_t total = 0, most = 0;
  for (const std::int64_t count : voxels_per_offset) {
    total += count;
    most = std::max(most, count);
  }
  return total > 0 ? double(most) / double(total) : 0.0;
}

} // namespace texsim::pipelines::solid_synthesis
