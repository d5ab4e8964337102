#pragma once
/// n-way orientation relaxation (Wei & Levoy 2001, Section 3.1). With phi_qp = relative_angle()
/// (radians) and d_n = symmetric_residue(), vertex p's energy is
///   E_p = sum over q of d_n(phi_qp)^2,
/// q running over p's 1-ring and, on a finer level, the three vertices of p's parent face (fixed
/// coarser-level values). Pairs with opposite normals are left out. Because phi_pq = -phi_qp, the
/// 1-ring terms are pair terms, and the total energy (radians squared)
///   E = sum over edges d_n(phi)^2 + sum over vertices and their parent-face vertices d_n(phi)^2
///     = sum_p (E_p^ring / 2 + E_p^parent)
/// changes by exactly the change of E_p when s_p alone moves: setting s_p to the exact minimiser of
/// E_p never raises E (up to rounding).
#include "geom/mesh_topology.hpp"
#include "geom/triangle_mesh.hpp"
#include "par/comm.hpp"
#include "pipelines/surface_synthesis/orientation_field.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// E_p(theta) = sum_q d_n(angles[q] - theta)^2 for the neighbour angles phi_qp (radians).
double rotation_energy(std::span<const double> angles, int symmetry, double theta);

/// The exact minimiser of rotation_energy() over theta, in [0, 2 pi / symmetry): the angles are
/// sorted modulo 2 pi / n; each of the m cyclic cuts between consecutive sorted angles unwraps them
/// into one arrangement whose mean is a candidate; every candidate is evaluated exactly and the
/// lowest wins (ties to the earlier cut). Returns 0 for no angles.
double minimising_rotation(std::span<const double> angles, int symmetry);

struct RelaxationReport {
  std::vector<double> energy;      ///< total E after each sweep, energy[0] = before
  std::int32_t colour_classes = 0; ///< classes of the greedy colouring of the 1-ring graph
};

/// `sweeps` Gauss-Seidel sweeps over the colour classes of the 1-ring graph (greedy colouring in id
/// order, so the classes do not depend on the rank count); each update rotates s_p about n_p by
/// the exact minimiser of E_p over the 1-ring (and the parent-face vertices when `coarser` is
/// given and has parents); a rotation that does not lower E_p strictly leaves s_p untouched.
/// Updated directions are unit vectors in their tangent planes.
///
/// Distribution: `rings` are the 1-rings of this rank's run [rank_offsets[r], rank_offsets[r+1])
/// (run_rings: row i for vertex rank_offsets[r] + i, the level's vertex ids), and `normals` and
/// `directions` hold that run only, and `coarser` one entry per run vertex. Each rank fetches
/// its ring halo's directions and normals from their owners, updates its run's members of each
/// class (OpenMP threads share them) and sends their new directions to the ranks whose rings hold
/// them. The total energy is a par::reproducible_sum of the vertices' shares. The directions are
/// the same bits on return for any rank count and thread count, and so is the energy. rank_offsets
/// has comm.size + 1 non-decreasing entries from 0 to the vertex count. `symmetry` n >= 1, sweeps
/// >= 0. Collective.
RelaxationReport relax_directions(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                                  const geom::CsrAdjacency& rings,
                                  std::span<const geom::Vec3> normals,
                                  const CoarserOrientation* coarser, int symmetry, int sweeps,
                                  std::vector<geom::Vec3>& directions);

} // namespace texsim::pipelines::surface_synthesis
