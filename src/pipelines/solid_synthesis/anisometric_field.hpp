#pragma once
/// Anisometric control of solid synthesis (Su 2008 chapter 4, after Lefebvre & Hoppe 2005): a
/// field of local frames over the output volume, and its per-level Jacobians.
///
/// A field gives, at each point x of the output volume (unit coordinates, [0, 1)^3), a 3x3 matrix
/// F(x) whose COLUMNS are the directions in output space along which the exemplar's x, y and z
/// axes appear, each as long as the local scale of the exemplar features (1 = exemplar scale).
/// The synthesis uses the Jacobian A = F^-1 (output displacement -> exemplar displacement) and
/// its inverse A^-1 = F. A constant rotation R by +theta about z gives F = R: the synthesized
/// pattern is the exemplar turned by +theta.
///
/// The built-in fields reconstruct the controls of the thesis' section 5.2 (whose figures our
/// transcription lacks); all are rotations (unit scale) except the vector-grid field:
/// - identity: F = I everywhere (isometric synthesis).
/// - ellipse (`circular`, `oval`): on every XY plane the exemplar x axis follows the
///   counter-clockwise tangent of the ellipses around the volume centre whose x semi-axis is
///   `ratio` times the y one (ratio 1: circles), the y axis points inwards along the ellipse
///   normal (so F is a rotation and the exemplar is not mirrored), z stays z. At the centre
///   itself, where no direction is defined, F = I.
/// - rotation (`slant`, `slant3d`): a constant rotation by an angle about an axis: z for the
///   slant of XY planes, (1, 1, 1)/sqrt(3) for the 3D slant that tilts every cross section.
/// - zigzag: a rotation about z by angle * s(y), with s a smoothed square wave,
///   s(y) = tanh(3 sin(pi bands y)) / tanh(3), alternating between +1 and -1 in `bands` bands
///   along y (the switch takes about a third of a band). Even band counts tile across the y seam.
/// - vector grid: a grid of vectors v stretched over the unit cube (voxel centres at
///   (i + 1/2) / n) and interpolated trilinearly with clamping; v is the exemplar x axis
///   (direction and scale), y and z are unit axes completing a right-handed frame by
///   Gram-Schmidt against z (against y where v is parallel to z). F = I where v = 0.
#include "vol/dense_grid.hpp"

#include <Eigen/Dense>

#include <cstddef>
#include <memory>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// A field of exemplar frames over the output volume. Implementations are immutable, so axes()
/// may be called from many threads at once.
class AxesField {
public:
  virtual ~AxesField() = default;
  /// F at a point of the output volume, unit coordinates ([0, 1)^3; outside, the field's formula
  /// extended, or clamped for grids). Columns: the exemplar's x, y, z axes in output space.
  virtual Eigen::Matrix3d axes(const Eigen::Vector3d& unit_position) const = 0;
};

/// The Jacobian A_l and its inverse A_l^-1 for the voxels of z-planes [z_begin, z_end) of one
/// pyramid level of `level_size`^3 voxels.
struct LevelJacobians {
  int level_size = 0;
  int z_begin = 0;
  int z_end = 0;
  /// A_l (output displacement -> exemplar displacement) and A_l^-1 per voxel, index
  /// i + n * (j + n * (k - z_begin)).
  std::vector<Eigen::Matrix3f> jacobian, inverse;

  /// A_l at voxel (i, j, k), 0 <= i, j < level_size, z_begin <= k < z_end.
  const Eigen::Matrix3f& a(int i, int j, int k) const { return jacobian[index(i, j, k)]; }
  /// A_l^-1 at voxel (i, j, k).
  const Eigen::Matrix3f& a_inverse(int i, int j, int k) const { return inverse[index(i, j, k)]; }
  /// A_l at voxel (i, j, k) with i and j any integers (periodic, as the level is), k within the
  /// sampled planes.
  const Eigen::Matrix3f& a_periodic(int i, int j, int k) const {
    return a((i % level_size + level_size) % level_size, (j % level_size + level_size) % level_size,
             k);
  }

private:
  std::size_t index(int i, int j, int k) const;
};

/// |det| below which an averaged frame counts as singular and is replaced by the identity (the
/// exemplar at its own scale): e.g. the centre of the circular field, where the tangents of a
/// coarse voxel cancel out.
inline constexpr double kSingularFrameDeterminant = 1e-3;

/// A_l^-1 at each voxel of planes [z_begin, z_end) of level `level_size` is the box average of F
/// over the unit-cube region the voxel covers ("made by downsampling the 3D vector field"),
/// estimated at a fixed stratified sample: the centres of s x s x s sub-cells with
/// s = min(4, finest_size / level_size), i.e. the finest level's voxel centres while they are at
/// most 4 per axis, and the voxel centre itself on the finest level. A_l is its inverse; singular
/// averages (|det| < kSingularFrameDeterminant) become the identity. Planes outside
/// [0, level_size) wrap (the volume is a 3-torus), so halo planes can be sampled too.
/// level_size must divide finest_size. Deterministic; OpenMP over planes. Not collective.
LevelJacobians sample_level(const AxesField& field, int level_size, int z_begin, int z_end,
                            int finest_size);

/// F = I.
std::unique_ptr<AxesField> identity_field();
/// Tangents of ellipses around the volume centre on every XY plane, x semi-axis `ratio` times the
/// y one (1: circles); ratio > 0.
std::unique_ptr<AxesField> ellipse_field(double ratio);
/// A constant rotation by `angle_degrees` (counter-clockwise looking down the axis) about `axis`.
std::unique_ptr<AxesField> rotation_field(const Eigen::Vector3d& axis, double angle_degrees);
/// Rotation about z by +-`angle_degrees`, alternating in `bands` smooth bands along y; bands > 0.
std::unique_ptr<AxesField> zigzag_field(double angle_degrees, int bands);
/// The frames of a grid of exemplar x axis vectors (r, g, b = x, y, z components).
std::unique_ptr<AxesField> vector_grid_field(vol::RgbGrid vectors);

/// The right-handed frame whose x axis is `x_axis` and whose y and z axes are unit vectors from
/// Gram-Schmidt against z (against y when `x_axis` is parallel to z); the identity for a zero
/// vector.
Eigen::Matrix3d frame_from_x_axis(const Eigen::Vector3d& x_axis);

} // namespace texsim::pipelines::solid_synthesis
