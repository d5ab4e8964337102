#pragma once
/// The quality measures of summary.json taken on the finished synthesis where it lies: every rank
/// measures its own slab, so no rank needs the whole result. Each gives the same value on every
/// rank and for any rank count (partial results travel to rank 0 and are added there in the
/// volume's order, or are exact integer counts).
#include "pipelines/solid_synthesis/anisometric_field.hpp"
#include "pipelines/solid_synthesis/appearance_space.hpp"
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "vol/channel_grid.hpp"

#include <array>

namespace texsim::pipelines::solid_synthesis {

/// neighbourhood_error (synthesis_metrics.hpp) of the result cropped to `dims`, the exemplar's
/// colours at S, sampled at the voxels whose coordinates are multiples of `stride`, each
/// neighbourhood read from the synthesized level around it (periodic in x and y at the level's
/// size, z from the slab's halo, which must be current): a crop smaller than the level does not
/// count seams of its own. `finest` is the finest appearance level (window at most
/// 2 kSlabHalo + 1).
///
/// Under an anisometric field (`jacobians` of the finest level's owned planes and kSlabHalo
/// planes beyond; null: isometric) the neighbourhood is taken in the field's frame, the frame the
/// synthesis matches in: window offset delta lies at p + A^-1 delta, read through its nearest
/// voxel q as the exemplar colour at S[q] + delta - (A_p + A_q) / 2 (q - p). An axis-aligned window
/// would count every correctly turned edge as an error (a rotated copy of bricks never matches the
/// upright exemplar); this one is 0 for an exactly warped copy and equals the axis-aligned window
/// for A = I. Collective.
double slab_neighbourhood_error(const par::Comm& comm, const CoordinateSlab& slab,
                                const LevelJacobians* jacobians, const std::array<int, 3>& dims,
                                const AppearanceLevel& finest,
                                const vol::ChannelGrid& exemplar_colours, int stride);

/// histogram_distance (synthesis_metrics.hpp) between the colours of the result cropped to
/// `dims` and the exemplar's. Collective.
double slab_histogram_distance(const par::Comm& comm, const CoordinateSlab& slab,
                               const std::array<int, 3>& dims,
                               const vol::ChannelGrid& exemplar_colours);

} // namespace texsim::pipelines::solid_synthesis
