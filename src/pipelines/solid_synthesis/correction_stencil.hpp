#pragma once
/// Where the voxel correction of one voxel p reads: the 8 diagonal neighbours of eq. (3), each
/// averaged over 4 sub-neighbours (eq. (4)), and the neighbours whose similarity sets propose the
/// 24 candidates; warped by the anisometric field in chapter 4 (eqs. (6)-(7)).
///
/// One formula covers both cases. A synthesized voxel q predicts p's exemplar coordinate as
/// S[q] - h A (q - p) (A maps output displacements to exemplar ones, h = h_l the level's spacing),
/// so the exemplar position of p's neighbour Delta, read through q, is S[q] - h A (q - p) + h
/// Delta. With A = I and q = p + Delta + M Delta this is eq. (4), S[p + Delta + Delta'] - Delta' h;
/// the thesis prints it without h, which is only right at the finest level (h = 1). The warped
/// neighbour directions are phi~(Delta) = A^-1 Delta / |A^-1 Delta| rounded to the nearest voxel
/// (Lefebvre and Hoppe 2005, section 6), which for A = I gives back Delta.
#include "pipelines/solid_synthesis/coordinate_slab.hpp"

#include <Eigen/Core>

#include <array>
#include <functional>

namespace texsim::pipelines::solid_synthesis {

/// The 8 diagonal directions (+-1, +-1, +-1), x fastest.
inline constexpr int kDiagonalCount = 8;
/// Sub-neighbours averaged per diagonal neighbour: M in {0, e_x e_x^T, e_y e_y^T, e_z e_z^T}.
inline constexpr int kSubNeighbourCount = 4;

struct CorrectionStencil {
  /// q - p for the neighbour that proposes candidates in direction Delta (phi~(Delta)).
  std::array<Coord, kDiagonalCount> source;
  /// h A (q - p) in fixed point: a candidate for p is C_i(S[q]) + (S[q]'s fraction) -
  /// source_shift.
  std::array<Position, kDiagonalCount> source_shift;
  /// q_M - p for the 4 sub-neighbours of direction Delta.
  std::array<std::array<Coord, kSubNeighbourCount>, kDiagonalCount> sample;
  /// -h A (q_M - p) + h Delta in fixed point: added to S[q_M] gives the exemplar position whose
  /// nearest voxel's feature enters the average of eq. (4)/(7).
  std::array<std::array<Position, kSubNeighbourCount>, kDiagonalCount> sample_shift;
  /// h Delta: the exemplar neighbourhood N_E(u) reads u + h Delta.
  std::array<Coord, kDiagonalCount> exemplar_offset;
};

/// A_l at p + offset, for a field that varies between voxels.
using NeighbourJacobian = std::function<const Eigen::Matrix3f&(const Coord& offset)>;

/// The stencil at spacing h for Jacobian A and its inverse at p (identity: the isometric case).
/// Without `neighbour` every prediction uses A: h A (q - p). With it, a prediction through q uses
/// the mean of the Jacobians at its two ends, h (A_p + A_q) / 2 (q - p): the trapezoid rule for
/// the exemplar displacement along a field that turns between p and q, exact to second order
/// where A_p alone is exact to first (a circular field turns 1/r radians a voxel at radius r). A
/// uniform field gives the same bits either way. A pure function of (h, A, A^-1 and the A_q),
/// evaluated in batches that give the bits of the per-entry Eigen formula
/// (coordinate_slab_test.cpp compares the two): every anisometric voxel needs its own.
CorrectionStencil make_stencil(int h, const Eigen::Matrix3f& jacobian,
                               const Eigen::Matrix3f& inverse_jacobian,
                               const NeighbourJacobian& neighbour = {});

/// v voxels as a fixed-point position: round(2^kSubvoxelBits v), halves up.
Position fixed_point(const Eigen::Vector3f& v);

/// h A (c - 1/2) in fixed point for child c in {0,1}^3 (x fastest): eq. (5)'s child offset. With
/// A = I children are h apart, as in eq. (1) up to a constant shift.
std::array<Position, 8> child_offsets(int h, const Eigen::Matrix3f& jacobian);

} // namespace texsim::pipelines::solid_synthesis
