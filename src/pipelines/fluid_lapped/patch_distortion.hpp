#pragma once
/// How distorted a patch is (section 5.2): the distortion delta_t of each triangle between its
/// rest shape and its current shape, the triangle quality Q_T (equation 1), and the per-vertex
/// erosion weight w_V = Q_V B_V (equations 2 and 3).
#include "pipelines/fluid_lapped/patch.hpp"

#include <Eigen/Core>

#include <array>

namespace texsim::pipelines::fluid_lapped {

/// delta_t = max(s1, 1 / s2), s1 >= s2 the singular values of the Jacobian of the affine map
/// from the rest triangle (2D, model units) to the current one (3D, measured in its own plane):
/// the stretch metric of Sorkine et al. 2002 the paper cites. 1 for a rigid motion, 2 for a
/// stretch by 2 or a shrink by 1/2; +infinity when either triangle is degenerate.
double triangle_distortion(const std::array<Eigen::Vector2d, 3>& rest,
                           const std::array<geom::Vec3, 3>& current);

/// Q_T = max((delta_max - delta) / (delta_max - 1), 0) (equation 1).
double triangle_quality(double delta, double delta_max);

/// Sets patch.weights: Q_V is the mean Q_T over the vertex's triangles (rest shape = rest_uv x 2r),
/// B_V = 0 on a boundary vertex of the current triangles whose rest distance to p
/// (|uv - (0.5, 0.5)| x 2r) exceeds r / 4 and that is not a corner of the triangle holding p
/// (rest uv (0.5, 0.5))†, else 1 (equation 2); w_V = Q_V B_V, 0 for a vertex no triangle uses.
void update_weights(Patch& patch, double radius, double delta_max = 3.0);

} // namespace texsim::pipelines::fluid_lapped
