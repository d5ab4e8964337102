#pragma once
/// Assembly of P1 (linear) finite element matrices on a DistributedMesh: each rank computes the
/// rows it owns from the triangles touching its vertices (no off-process entries), into
/// MATMPIAIJ matrices that all share one sparsity pattern, so a matrix is updated in place and
/// only the terms whose coefficients change are recomputed (Bajaj et al., section 4).
///
/// Integrals are exact for coefficients given at vertices and interpolated linearly:
///   mass       M_ij = int w phi_i phi_j      (w P1: A/60 * {6,2,1} weights per vertex triple)
///   stiffness  K_ij = int (T grad phi_i) . grad phi_j   (T P1: area * mean vertex tensor)
/// Coefficient arrays are indexed by local vertex (owned first, then ghosts; DistributedMesh).
///
/// OpenMP threads compute the elements' 3 x 3 blocks, then each value sums its elements' entries
/// in increasing element order, as one thread adding element after element would: the values
/// are the same bytes for any number of threads.
#include "geom/distributed_mesh.hpp"
#include "par/comm.hpp"
#include "par/petsc_handle.hpp"

#include <Eigen/Core>

#include <array>
#include <span>
#include <vector>

namespace texsim::pipelines::fem_rd {

class P1Assembler {
public:
  /// Builds the pattern of this rank's rows (the vertex and its neighbours) and the element
  /// geometry of the mesh's current positions. Not collective.
  explicit P1Assembler(const geom::DistributedMesh& mesh);

  /// Recomputes the element geometry (areas, gradients) after the mesh moved.
  void update_geometry();

  /// A MATMPIAIJ matrix with this pattern and zero values. Collective.
  par::PetscMat create_matrix(const par::Comm& comm) const;

  /// Values (in pattern order) of the mass matrix with per-vertex weight `weight` (empty: 1);
  /// `lumped` puts each row sum on the diagonal. Uses the geometry of the last update.
  std::vector<double> mass_values(std::span<const double> weight, bool lumped) const;

  /// Values of the stiffness matrix with per-vertex symmetric tensors (9 per local vertex,
  /// row-major; empty: the identity, i.e. the cotangent Laplacian).
  std::vector<double> stiffness_values(std::span<const double> tensors) const;

  /// Copies pattern-ordered values into `matrix` (created by create_matrix). Collective.
  void set_values(Mat matrix, const std::vector<double>& values) const;

  /// Number of stored values of this rank's rows.
  std::size_t value_count() const { return columns_.size(); }

private:
  const geom::DistributedMesh& mesh_;
  std::vector<PetscInt> row_offsets_; ///< local row -> first entry
  std::vector<PetscInt> columns_;     ///< global column ids, sorted within each row
  /// For each assembly triangle: slot of entry (corner i, corner j) in the values, or -1 when
  /// corner i's row is not owned here.
  std::vector<std::array<std::int64_t, 9>> slots_;
  /// For each assembly triangle: local indices of its corners (for coefficient arrays).
  std::vector<std::array<std::int32_t, 3>> corners_;
  /// For each assembly triangle: area and the gradients of its three P1 functions.
  std::vector<double> areas_;
  std::vector<std::array<Eigen::Vector3d, 3>> gradients_;
  /// For each value: the element entries (9 e + 3 i + j) that add into it, increasing
  /// (entries [source_offsets_[v], source_offsets_[v + 1]) of sources_).
  std::vector<std::int64_t> source_offsets_;
  std::vector<std::int64_t> sources_;

  /// The values from every element's 9 entries (9 per assembly triangle).
  std::vector<double> sum_entries(const std::vector<double>& entries) const;
};

} // namespace texsim::pipelines::fem_rd
