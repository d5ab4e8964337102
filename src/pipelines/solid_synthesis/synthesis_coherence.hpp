#pragma once
/// How coherent a synthesized volume is: a voxel copies its exemplar neighbourhood coherently
/// when a neighbour continues its exemplar coordinate (S(p + e) = S(p) + A e, A the field's
/// Jacobian, the identity for isometric synthesis). Isolated voxels that no neighbour continues
/// are the salt-and-pepper speckles of a correction that accepted incoherent candidates.
#include "par/comm.hpp"
#include "pipelines/solid_synthesis/anisometric_field.hpp"
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "vol/dense_grid.hpp"

#include <Eigen/Core>

#include <array>
#include <optional>

namespace texsim::pipelines::solid_synthesis {

/// Fraction of the voxels of the box [0, crop) whose exemplar position none of their 6 axis
/// neighbours continues: for every e in {+-x, +-y, +-z}, the nearest voxel of S(p + e) differs
/// (modulo the exemplar size) from the nearest voxel of S(p) + (A(p) + A(p + e)) / 2 e (in fixed
/// point, as the synthesis predicts). `jacobians` (null: A = I) cover the slab's owned planes and
/// one plane beyond. The slab's halo
/// must be current. Collective: counts over every rank's owned planes (a replicated level once).
double incoherent_fraction(const par::Comm& comm, const CoordinateSlab& slab,
                           const LevelJacobians* jacobians, const vol::Dims& exemplar,
                           const std::array<int, 3>& crop);

/// Fraction of the voxels of the box [0, crop) that share the most common offset S(p) - A p
/// (its nearest voxel, modulo the exemplar size; A = I when `uniform_jacobian` is null): 1 /
/// (number of voxels) for a volume of isolated copies, near 1 for one shifted (or, under a
/// uniform field, one turned) copy of the exemplar. Read with incoherent_fraction: low
/// incoherence says little when one offset holds most of the volume. Needs A the same at every
/// voxel (a warped copy under a varying field has no constant offset). Collective: one count per
/// exemplar voxel, summed over ranks.
double largest_offset_share(const par::Comm& comm, const CoordinateSlab& slab,
                            const Eigen::Matrix3f* uniform_jacobian, const vol::Dims& exemplar,
                            const std::array<int, 3>& crop);

/// A_l if it is the same (to the bit) at every voxel of `jacobians` on every rank, else nullopt.
/// Collective.
std::optional<Eigen::Matrix3f> uniform_jacobian(const par::Comm& comm,
                                                const LevelJacobians& jacobians);

} // namespace texsim::pipelines::solid_synthesis
