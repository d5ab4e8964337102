#pragma once
/// Assembly of P1 (linear) finite element matrices on a DistributedMesh (a FemAssembler; the
/// pattern and sums are ElementAssembly's): each rank computes the
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
#include "pipelines/fem_rd/fem_assembler.hpp"

#include <Eigen/Core>

#include <array>
#include <span>
#include <vector>

namespace texsim::pipelines::fem_rd {

class P1Assembler final : public FemAssembler {
public:
  /// Builds the pattern of this rank's rows (the vertex and its neighbours) and the element
  /// geometry of the mesh's current positions. Not collective.
  explicit P1Assembler(const geom::DistributedMesh& mesh);

  /// Recomputes the element geometry (areas, gradients) after the mesh moved.
  void update_geometry() override;
  std::vector<double> mass_values(std::span<const double> weight, bool lumped) const override;
  std::vector<double> stiffness_values(std::span<const double> tensors) const override;
  std::int32_t coefficient_count() const override { return mesh_.local_count(); }
  std::string description() const override {
    return "P1 hats, " + std::to_string(corners_.size()) + " elements";
  }

private:
  const geom::DistributedMesh& mesh_;
  /// For each assembly triangle: local indices of its corners (for coefficient arrays).
  std::vector<std::array<std::int32_t, 3>> corners_;
  /// For each assembly triangle: area and the gradients of its three P1 functions.
  std::vector<double> areas_;
  std::vector<std::array<Eigen::Vector3d, 3>> gradients_;
};

} // namespace texsim::pipelines::fem_rd
