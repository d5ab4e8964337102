#include "pipelines/solid_synthesis/correction_stencil.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace texsim::pipelines::solid_synthesis {
namespace {

Coord rounded(const Eigen::Vector3f& v) {
  return {static_cast<std::int32_t>(std::floor(v.x() + 0.5f)),
          static_cast<std::int32_t>(std::floor(v.y() + 0.5f)),
          static_cast<std::int32_t>(std::floor(v.z() + 0.5f))};
}

Eigen::Vector3f as_vector(const Coord& c) {
  return {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
}

/// phi~(d): the output direction A^-1 d with its length removed, rounded to a voxel offset.
Coord warped_direction(const Eigen::Matrix3f& inverse_jacobian, const Eigen::Vector3f& d) {
  const Eigen::Vector3f phi = inverse_jacobian * d;
  const float length = phi.norm();
  if (!(length > 0.0f))
    return rounded(d.normalized());
  return rounded(phi / length);
}

Eigen::Vector3f diagonal(int index) {
  return {index & 1 ? 1.0f : -1.0f, index & 2 ? 1.0f : -1.0f, index & 4 ? 1.0f : -1.0f};
}

} // namespace

CorrectionStencil make_stencil(int h, const Eigen::Matrix3f& jacobian,
                               const Eigen::Matrix3f& inverse_jacobian) {
  const auto shift = [&](const Coord& offset) {
    return rounded(static_cast<float>(h) * (jacobian * as_vector(offset)));
  };
  CorrectionStencil stencil;
  for (int d = 0; d < kDiagonalCount; ++d) {
    const Eigen::Vector3f delta = diagonal(d);
    const Coord h_delta = rounded(static_cast<float>(h) * delta);
    stencil.exemplar_offset[d] = h_delta;
    stencil.source[d] = warped_direction(inverse_jacobian, delta);
    stencil.source_shift[d] = shift(stencil.source[d]);
    for (int m = 0; m < kSubNeighbourCount; ++m) {
      Coord offset = stencil.source[d];
      if (m > 0) {
        Eigen::Vector3f axis_part = Eigen::Vector3f::Zero();
        axis_part[m - 1] = delta[m - 1];
        offset = offset + warped_direction(inverse_jacobian, axis_part);
      }
      stencil.sample[d][m] = offset;
      stencil.sample_shift[d][m] = h_delta - shift(offset);
    }
  }
  return stencil;
}

std::array<Coord, 8> child_offsets(int h, const Eigen::Matrix3f& jacobian) {
  std::array<Coord, 8> offsets;
  for (int c = 0; c < 8; ++c)
    offsets[c] = rounded(static_cast<float>(h) * (jacobian * (0.5f * diagonal(c))));
  return offsets;
}

} // namespace texsim::pipelines::solid_synthesis
