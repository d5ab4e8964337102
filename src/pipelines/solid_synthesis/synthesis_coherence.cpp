#include "pipelines/solid_synthesis/synthesis_coherence.hpp"

#include "pipelines/solid_synthesis/correction_stencil.hpp"

#include "core/error.hpp"
#include "vol/channel_grid.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

double incoherent_fraction(const par::Comm& comm, const CoordinateSlab& slab,
                           const LevelJacobians* jacobians, const vol::Dims& exemplar,
                           const std::array<int, 3>& crop) {
  const LevelLayout& layout = slab.layout();
  TEXSIM_VERIFY(
      !jacobians || layout.z_begin == layout.z_end ||
          (jacobians->z_begin <= layout.z_begin - 1 && jacobians->z_end >= layout.z_end + 1),
      "incoherent_fraction: the Jacobians must cover the owned planes and one beyond");
  const auto same = [&](const Coord& a, const Coord& b) {
    return vol::ChannelGrid::wrap(a.x - b.x, exemplar.nx) == 0 &&
           vol::ChannelGrid::wrap(a.y - b.y, exemplar.ny) == 0 &&
           vol::ChannelGrid::wrap(a.z - b.z, exemplar.nz) == 0;
  };
  const bool counts = !layout.replicated || comm.is_root();
  const int z_end = counts ? std::min(layout.z_end, crop[2]) : layout.z_begin;
  std::int64_t incoherent = 0, voxels = 0;
#pragma omp parallel for schedule(static) reduction(+ : incoherent, voxels)
  for (int k = layout.z_begin; k < z_end; ++k)
    for (int j = 0; j < crop[1]; ++j)
      for (int i = 0; i < crop[0]; ++i) {
        const Position s = slab.at(i, j, k);
        bool continued = false;
        for (int axis = 0; axis < 3 && !continued; ++axis)
          for (const int sign : {-1, 1}) {
            Position step{0, 0, 0};
            if (jacobians) {
              // Mean of the two ends' Jacobians, as the synthesis predicts (make_stencil).
              const Eigen::Matrix3f mean =
                  (jacobians->a(i, j, k) + jacobians->a_periodic(i + (axis == 0 ? sign : 0),
                                                                 j + (axis == 1 ? sign : 0),
                                                                 k + (axis == 2 ? sign : 0))) *
                  0.5f;
              step = fixed_point(mean.col(axis) * float(sign));
            } else {
              (axis == 0 ? step.x : axis == 1 ? step.y : step.z) = sign << kSubvoxelBits;
            }
            const Position neighbour = slab.at(
                i + (axis == 0 ? sign : 0), j + (axis == 1 ? sign : 0), k + (axis == 2 ? sign : 0));
            if (same(neighbour.voxel(), (s + step).voxel())) {
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
                            const Eigen::Matrix3f* uniform_jacobian, const vol::Dims& exemplar,
                            const std::array<int, 3>& crop) {
  const Eigen::Matrix3f a =
      uniform_jacobian ? *uniform_jacobian : Eigen::Matrix3f(Eigen::Matrix3f::Identity());
  const LevelLayout& layout = slab.layout();
  const bool counts = !layout.replicated || comm.is_root();
  const int z_end = counts ? std::min(layout.z_end, crop[2]) : layout.z_begin;
  std::vector<std::int64_t> voxels_per_offset(std::size_t(exemplar.nx) * exemplar.ny * exemplar.nz);
  for (int k = layout.z_begin; k < z_end; ++k)
    for (int j = 0; j < crop[1]; ++j)
      for (int i = 0; i < crop[0]; ++i) {
        const Coord s =
            (slab.at(i, j, k) - fixed_point(a * Eigen::Vector3f(float(i), float(j), float(k))))
                .voxel();
        const std::size_t offset =
            (std::size_t(vol::ChannelGrid::wrap(s.z, exemplar.nz)) * exemplar.ny +
             std::size_t(vol::ChannelGrid::wrap(s.y, exemplar.ny))) *
                exemplar.nx +
            std::size_t(vol::ChannelGrid::wrap(s.x, exemplar.nx));
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

std::optional<Eigen::Matrix3f> uniform_jacobian(const par::Comm& comm,
                                                const LevelJacobians& jacobians) {
  // Rank 0's first matrix (identity where it holds none) against every matrix of every rank.
  Eigen::Matrix3f first = jacobians.jacobian.empty() ? Eigen::Matrix3f(Eigen::Matrix3f::Identity())
                                                     : jacobians.jacobian.front();
  MPI_Bcast(first.data(), 9, MPI_FLOAT, 0, comm.raw);
  int uniform = std::all_of(jacobians.jacobian.begin(), jacobians.jacobian.end(),
                            [&](const Eigen::Matrix3f& a) {
                              return std::memcmp(a.data(), first.data(), sizeof(float) * 9) == 0;
                            })
                    ? 1
                    : 0;
  MPI_Allreduce(MPI_IN_PLACE, &uniform, 1, MPI_INT, MPI_LAND, comm.raw);
  if (!uniform)
    return std::nullopt;
  return first;
}

} // namespace texsim::pipelines::solid_synthesis
