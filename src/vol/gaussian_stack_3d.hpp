#pragma once
/// Gaussian stacks of volumes (Lefebvre & Hoppe 2005, in 3D): every level has the exemplar's dims,
/// level s holds the features of pyramid level s at every voxel, so neighbourhoods of level s are
/// read with taps 2^s voxels apart.
#include "vol/channel_grid.hpp"

#include <span>
#include <vector>

namespace texsim::vol {

/// Number of levels after the exemplar: the smallest S with 2^S >= the largest of `dims`.
int coarsest_stack_level(Dims dims);

/// The separable binomial blur [1 4 6 4 1] / 16 along x, y and z with taps `spacing` voxels apart
/// ("a trous"); reads wrap around the grid when `periodic`, otherwise clamp to the border.
/// OpenMP over z-slices; the result does not depend on the thread count.
ChannelGrid binomial_blur_3d(const ChannelGrid& grid, int spacing, bool periodic);

/// Planes [z_begin, z_end) of binomial_blur_3d(grid, spacing, periodic), the same bytes, into
/// `out` (those planes' values, x fastest): only the planes the z taps read are blurred along x
/// and y, so ranks that each compute a share of the planes do not repeat each other's work.
void binomial_blur_3d_planes(const ChannelGrid& grid, int spacing, bool periodic, int z_begin,
                             int z_end, std::span<float> out);

/// Levels s = 0..S (S = coarsest_stack_level(exemplar.dims())): [0] is the exemplar, [s + 1] is
/// [s] blurred with taps 2^s apart. Periodic stacks preserve the mean at every level, and when the
/// dims are powers of two the coarsest level is the exemplar's mean at every voxel (up to float
/// rounding).
std::vector<ChannelGrid> gaussian_stack(const ChannelGrid& exemplar, bool periodic);

} // namespace texsim::vol
