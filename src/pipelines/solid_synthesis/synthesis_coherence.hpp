#pragma once
/// How coherent a synthesized volume is: a voxel copies its exemplar neighbourhood coherently
/// when a neighbour continues its exemplar coordinate (S(p + e) = S(p) + A e, A the field's
/// Jacobian, the identity for isometric synthesis). Isolated voxels that no neighbour continues
/// are the salt-and-pepper speckles of a correction that accepted incoherent candidates.
#include "par/comm.hpp"
#include "pipelines/solid_synthesis/anisometric_field.hpp"
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "vol/dense_grid.hpp"

#include <array>

namespace texsim::pipelines::solid_synthesis {

/// Fraction of the voxels of the box [0, crop) whose exemplar coordinate none of their 6 axis
/// neighbours continues: for every e in {+-x, +-y, +-z}, S(p + e) differs (modulo the exemplar
/// size) from S(p) + round(A(p) e), rounding each component to the nearest integer as the
/// upsampling does. `jacobians` (null: A = I) cover the slab's owned planes. The slab's halo must
/// be current. Collective: counts over every rank's owned planes (a replicated level once).
double incoherent_fraction(const par::Comm& comm, const CoordinateSlab& slab,
                           const LevelJacobians* jacobians, const vol::Dims& exemplar,
                           const std::array<int, 3>& crop);

/// Fraction of the voxels of the box [0, crop) that share the most common offset S(p) - p
/// (modulo the exemplar size): 1 / (number of voxels) for a volume of isolated copies, near 1 for
/// one shifted copy of the exemplar. Read with incoherent_fraction: low incoherence says little
/// when one offset holds most of the volume. Meaningful for isometric synthesis only (a rotated
/// copy has no constant offset). Collective: one count per exemplar voxel, summed over ranks.
double largest_offset_share(const par::Comm& comm, const CoordinateSlab& slab,
                            const vol::Dims& exemplar, const std::array<int, 3>& crop);

} // namespace texsim::pipelines::solid_synthesis
