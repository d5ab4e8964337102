#pragma once
/// Texture orientation (Wei & Levoy 2001, Section 3.1): a unit tangent direction s per vertex of a
/// mesh level (t = n x s completes the frame). Random, user-field and inherited directions, and the
/// tangent-plane geometry they and the relaxation share: a fixed basis per normal, the minimal
/// rotation carrying one tangent plane onto another, signed angles. Angles are in radians
/// throughout. Every function is a pure function of its arguments, and all but the collective
/// fetch_frames() and coarser_orientation() are serial.
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"

#include <Eigen/Geometry> // cross products of tangent vectors

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// CounterRng stream of random_directions().
inline constexpr std::uint32_t kOrientationStream = 0x5701;

/// A vertex's parent face on the coarser level: the triangle, its three vertex ids there and the
/// barycentric weights of the hit point.
struct ParentFace {
  std::int32_t triangle = -1;
  std::array<std::int32_t, 3> vertices{-1, -1, -1};
  std::array<double, 3> weights{};
  bool found() const { return vertices[0] >= 0; }
};

/// The coarser level as a finer level's orientation reads it (fixed values), per vertex worked on:
/// its parent face and the directions and normals at the face's three corners (left unset where
/// no face was found).
struct CoarserOrientation {
  std::span<const ParentFace> parents;
  std::vector<std::array<geom::Vec3, 3>> directions; ///< unit tangents
  std::vector<std::array<geom::Vec3, 3>> normals;    ///< unit
};

/// The corners read from the coarser level's whole arrays (per coarser vertex). Serial.
CoarserOrientation coarser_orientation(std::span<const ParentFace> parents,
                                       std::span<const geom::Vec3> coarse_directions,
                                       std::span<const geom::Vec3> coarse_normals);

/// Directions and normals of some vertices of a level kept per run.
struct OwnersFrames {
  std::vector<geom::Vec3> directions;
  std::vector<geom::Vec3> normals;
};

/// The directions and normals at `ids` (in their order; repeats allowed) of a level whose run
/// [rank_offsets[r], rank_offsets[r + 1]) rank r holds (`directions`, `normals`), fetched from
/// their owners. Collective.
OwnersFrames fetch_frames(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                          std::span<const std::int64_t> ids, std::span<const geom::Vec3> directions,
                          std::span<const geom::Vec3> normals);

/// The same with the coarser level kept per run: `coarse_directions` and `coarse_normals` are
/// this rank's run [coarse_offsets[r], coarse_offsets[r + 1]) of the coarser level, and the
/// corners' values are fetched from their owners. The same values as the serial call.
/// Collective.
CoarserOrientation coarser_orientation(const par::Comm& comm, std::span<const ParentFace> parents,
                                       std::span<const std::int64_t> coarse_offsets,
                                       std::span<const geom::Vec3> coarse_directions,
                                       std::span<const geom::Vec3> coarse_normals);

/// A fixed orthonormal basis (e1, e2) of the plane normal to the unit vector n, with e2 = n x e1:
/// e1 is the normalised cross product of n with the coordinate axis least aligned with it (ties to
/// the lower axis), so it depends on n alone.
std::array<geom::Vec3, 2> tangent_basis(const geom::Vec3& n);

/// Bound on 1 + cos(angle between two normals) below which they count as opposite.
inline constexpr double kOppositeNormals = 1e-6;

/// `v` rotated by the minimal rotation taking unit normal `from` onto unit normal `to` (about
/// from x to). Opposite normals have no unique minimal rotation: std::nullopt when
/// 1 + from.to < kOppositeNormals.
std::optional<geom::Vec3> transport(const geom::Vec3& v, const geom::Vec3& from,
                                    const geom::Vec3& to);

/// Signed angle in [-pi, pi] from `from` to `to` measured counter-clockwise about the unit normal
/// n (both vectors are used through their components in the plane normal to n).
double signed_angle(const geom::Vec3& from, const geom::Vec3& to, const geom::Vec3& n);

/// phi_qp: the signed angle about n_p from s_p to s_q transported into p's tangent plane by the
/// minimal rotation n_q -> n_p. Antisymmetric up to rounding: phi_pq = -phi_qp. std::nullopt when
/// the normals are opposite (see transport()); such pairs take no part in orientation energies.
std::optional<double> relative_angle(const geom::Vec3& s_p, const geom::Vec3& n_p,
                                     const geom::Vec3& s_q, const geom::Vec3& n_q);

/// d_n: `angle` reduced modulo 2 pi / symmetry into [-pi / symmetry, pi / symmetry).
double symmetric_residue(double angle, int symmetry);

/// The unit tangent cos(angle) e1 + sin(angle) e2 in tangent_basis(n).
geom::Vec3 direction_at_angle(const geom::Vec3& n, double angle);

/// Random unit tangent directions of the vertices first, first + 1, ... (one per normal): vertex
/// v's angle is 2 pi U with U from CounterRng(seed, kOrientationStream).uniform(v, level), measured
/// in tangent_basis(normals[v - first]). Rank- and thread-count independent by construction.
/// Normals here and below are unit vectors, one per vertex worked on.
std::vector<geom::Vec3> random_directions(std::span<const geom::Vec3> normals, std::uint64_t seed,
                                          int level, std::int64_t first = 0);

/// Field vectors projected on each tangent plane and normalised. A vector (nearly) parallel to the
/// normal (projected length <= 1e-9 times its length, or zero) falls back to e1 of tangent_basis();
/// the number of such vertices goes to *degenerate_count when it is not null (the pipeline logs
/// it). Throws InputError naming the vertex when a field vector is not finite.
std::vector<geom::Vec3> projected_directions(std::span<const geom::Vec3> normals,
                                             std::span<const geom::Vec3> field,
                                             std::int64_t* degenerate_count);

/// Start of a finer level: each vertex interpolates its parent face's directions (transported into
/// its plane by transport()) as the unit complex numbers e^{i n theta}, weighted by the barycentric
/// weights, and takes theta = arg(sum) / n in tangent_basis(). Vertices without a parent face, and
/// those whose weighted sum (nearly) cancels (|sum| <= 1e-9), take random_fallback[v].
/// `symmetry` n >= 1; normals, random_fallback and `coarser` hold one entry per vertex worked on.
std::vector<geom::Vec3> inherited_directions(std::span<const geom::Vec3> normals,
                                             const CoarserOrientation& coarser, int symmetry,
                                             std::span<const geom::Vec3> random_fallback);

} // namespace texsim::pipelines::surface_synthesis
