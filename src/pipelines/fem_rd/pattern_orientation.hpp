#pragma once
/// Which way a pattern's stripes run against a tangent direction field (fem_rd.diffusion): the
/// area-weighted structure tensor of the P1 gradient of a species, each triangle's gradient
/// taken in its own frame (t, n x t), t the field's direction there. The dominant gradient
/// direction is across the stripes, so the stripes' angle to the field is 90 degrees from it.
#include "geom/distributed_mesh.hpp"
#include "pipelines/fem_rd/diffusion_field.hpp"

#include <span>

namespace texsim::pipelines::fem_rd {

struct StripeOrientation {
  double angle_to_field_deg = 0; ///< 0: stripes along the field, 90: across it
  double coherence = 0;          ///< (l1 - l2) / (l1 + l2) of the structure tensor: 1 all parallel
};

/// The orientation of `values` (per local vertex, owned and ghosts current) over the surface;
/// triangles where the field has no tangent direction are left out. The same bits at any rank
/// count (reproducible sums). Collective.
StripeOrientation stripe_orientation(const geom::DistributedMesh& mesh,
                                     std::span<const double> values, const DiffusionField& field);

} // namespace texsim::pipelines::fem_rd
