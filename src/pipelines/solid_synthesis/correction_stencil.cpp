#include "pipelines/solid_synthesis/correction_stencil.hpp"

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstdint>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// floor(x + 1/2): truncation toward zero, one lower where that rounded a negative value up.
/// The same integer as std::floor, which without SSE4.1 compiles to a branchy sequence.
std::int32_t rounded(float x) {
  const float t = x + 0.5f;
  const auto truncated = static_cast<std::int32_t>(t);
  return truncated - (t < static_cast<float>(truncated) ? 1 : 0);
}

Eigen::Vector3f diagonal(int index) {
  return {index & 1 ? 1.0f : -1.0f, index & 2 ? 1.0f : -1.0f, index & 4 ? 1.0f : -1.0f};
}

/// N 3-vectors as component arrays, so that the loops over them compile to SIMD code: every
/// voxel of an anisometric level has its own stencil, 14 normalised directions and 32 rounded
/// matrix-vector products.
template <int N> struct VectorBatch {
  std::array<float, N> x{}, y{}, z{};

  void set(int i, const Coord& c) {
    x[i] = static_cast<float>(c.x);
    y[i] = static_cast<float>(c.y);
    z[i] = static_cast<float>(c.z);
  }
};

template <int N> std::array<Coord, N> rounded(const VectorBatch<N>& v) {
  std::array<std::int32_t, N> x, y, z;
  for (int i = 0; i < N; ++i) {
    x[i] = rounded(v.x[i]);
    y[i] = rounded(v.y[i]);
    z[i] = rounded(v.z[i]);
  }
  std::array<Coord, N> out;
  for (int i = 0; i < N; ++i)
    out[i] = {x[i], y[i], z[i]};
  return out;
}

/// s M v for every v of the batch. Each component is summed as Eigen sums `s * (M * v)`,
/// s (m_r0 v_0 + (m_r1 v_1 + m_r2 v_2)), so that the stencil keeps the bits of its original
/// per-vector Eigen form (kept as the reference in coordinate_slab_test.cpp).
template <int N>
VectorBatch<N> product(float s, const Eigen::Matrix3f& m, const VectorBatch<N>& v) {
  VectorBatch<N> out;
  for (int i = 0; i < N; ++i) {
    out.x[i] = s * (m(0, 0) * v.x[i] + (m(0, 1) * v.y[i] + m(0, 2) * v.z[i]));
    out.y[i] = s * (m(1, 0) * v.x[i] + (m(1, 1) * v.y[i] + m(1, 2) * v.z[i]));
    out.z[i] = s * (m(2, 0) * v.x[i] + (m(2, 1) * v.y[i] + m(2, 2) * v.z[i]));
  }
  return out;
}

/// phi~(d) = A^-1 d / |A^-1 d| rounded to a voxel offset, for every d of the batch; |.| summed as
/// Eigen's norm(), sqrt(x^2 + (y^2 + z^2)). Where the length is 0 (or NaN) d stays as it is,
/// which is what rounding d / |d| gives for the diagonal and axis directions used here.
template <int N>
std::array<Coord, N> warped_directions(const Eigen::Matrix3f& inverse_jacobian,
                                       const VectorBatch<N>& d) {
  const VectorBatch<N> phi = product(1.0f, inverse_jacobian, d);
  std::array<float, N> length;
  for (int i = 0; i < N; ++i)
    length[i] = std::sqrt(phi.x[i] * phi.x[i] + (phi.y[i] * phi.y[i] + phi.z[i] * phi.z[i]));
  VectorBatch<N> unit;
  for (int i = 0; i < N; ++i) {
    unit.x[i] = phi.x[i] / length[i];
    unit.y[i] = phi.y[i] / length[i];
    unit.z[i] = phi.z[i] / length[i];
  }
  for (int i = 0; i < N; ++i)
    if (!(length[i] > 0.0f)) {
      unit.x[i] = d.x[i];
      unit.y[i] = d.y[i];
      unit.z[i] = d.z[i];
    }
  return rounded(unit);
}

/// Index of the signed axis direction Delta_m e_m among the warped directions: after the 8
/// diagonals, [8 + 2 m + (Delta_m > 0)].
constexpr int axis_direction(int axis, bool positive) {
  return kDiagonalCount + 2 * axis + (positive ? 1 : 0);
}

} // namespace

Position fixed_point(const Eigen::Vector3f& v) {
  constexpr float scale = 1 << kSubvoxelBits;
  return {rounded(scale * v.x()), rounded(scale * v.y()), rounded(scale * v.z())};
}

CorrectionStencil make_stencil(int h, const Eigen::Matrix3f& jacobian,
                               const Eigen::Matrix3f& inverse_jacobian,
                               const NeighbourJacobian& neighbour) {
  // The directions to warp: the 8 diagonals Delta, then the 6 signed axes, since
  // phi~(M Delta) = phi~(Delta_m e_m) whatever the other components of Delta.
  constexpr int kDirections = kDiagonalCount + 6;
  VectorBatch<kDirections> directions;
  for (int d = 0; d < kDiagonalCount; ++d)
    directions.set(d, {d & 1 ? 1 : -1, d & 2 ? 1 : -1, d & 4 ? 1 : -1});
  for (int axis = 0; axis < 3; ++axis)
    for (const bool positive : {false, true}) {
      const int sign = positive ? 1 : -1;
      directions.set(axis_direction(axis, positive),
                     {axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0});
    }
  const std::array<Coord, kDirections> warped = warped_directions(inverse_jacobian, directions);

  // Output offsets q - p: each diagonal's source, then its 3 sub-neighbours (M != 0).
  constexpr int kOffsets = kDiagonalCount * kSubNeighbourCount;
  VectorBatch<kOffsets> offsets;
  for (int d = 0; d < kDiagonalCount; ++d) {
    offsets.set(d * kSubNeighbourCount, warped[d]);
    for (int axis = 0; axis < 3; ++axis)
      offsets.set(d * kSubNeighbourCount + 1 + axis,
                  warped[d] + warped[axis_direction(axis, (d >> axis) & 1)]);
  }
  // h A (q - p) in fixed point: the scale 2^kSubvoxelBits h is exact in float.
  const float scale = static_cast<float>(h << kSubvoxelBits);
  std::array<Coord, kOffsets> shifts;
  if (!neighbour) {
    shifts = rounded(product(scale, jacobian, offsets));
  } else {
    VectorBatch<kOffsets> displacement;
    for (int at = 0; at < kOffsets; ++at) {
      const Coord offset{static_cast<std::int32_t>(offsets.x[at]),
                         static_cast<std::int32_t>(offsets.y[at]),
                         static_cast<std::int32_t>(offsets.z[at])};
      const Eigen::Matrix3f mean = (jacobian + neighbour(offset)) * 0.5f;
      VectorBatch<1> one;
      one.set(0, offset);
      const VectorBatch<1> moved = product(scale, mean, one);
      displacement.x[at] = moved.x[0];
      displacement.y[at] = moved.y[0];
      displacement.z[at] = moved.z[0];
    }
    shifts = rounded(displacement);
  }
  const auto position = [](const Coord& c) { return Position{c.x, c.y, c.z}; };

  CorrectionStencil stencil;
  for (int d = 0; d < kDiagonalCount; ++d) {
    const Coord h_delta{d & 1 ? h : -h, d & 2 ? h : -h, d & 4 ? h : -h};
    stencil.exemplar_offset[d] = h_delta;
    stencil.source[d] = warped[d];
    stencil.source_shift[d] = position(shifts[d * kSubNeighbourCount]);
    for (int m = 0; m < kSubNeighbourCount; ++m) {
      const int at = d * kSubNeighbourCount + m;
      stencil.sample[d][m] = {static_cast<std::int32_t>(offsets.x[at]),
                              static_cast<std::int32_t>(offsets.y[at]),
                              static_cast<std::int32_t>(offsets.z[at])};
      stencil.sample_shift[d][m] = Position::at_voxel(h_delta) - position(shifts[at]);
    }
  }
  return stencil;
}

std::array<Position, 8> child_offsets(int h, const Eigen::Matrix3f& jacobian) {
  std::array<Position, 8> offsets;
  for (int c = 0; c < 8; ++c)
    offsets[c] = fixed_point(static_cast<float>(h) * (jacobian * (0.5f * diagonal(c))));
  return offsets;
}

} // namespace texsim::pipelines::solid_synthesis
