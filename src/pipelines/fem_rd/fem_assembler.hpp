#pragma once
/// The finite element matrices of fem_rd's systems (eqs. 9-10) on a DistributedMesh, for one
/// choice of basis: P1 hats on the mesh (P1Assembler) or Loop's C1 box splines with the mesh as
/// control mesh (LoopAssembler). Each rank computes the rows it owns into MATMPIAIJ matrices of
/// one shared pattern; only the terms whose coefficients change are recomputed (section 4).
///
/// Coefficients are per-vertex arrays (local vertex index: owned, ghosts, then the rest of the
/// halo) expanded in the same basis, w = sum_k w_k phi_k:
///   mass       M_ij = int w phi_i phi_j
///   stiffness  K_ij = int (T grad phi_i) . grad phi_j,  T = sum_k T_k phi_k (9 per vertex)
#include "par/comm.hpp"
#include "par/petsc_handle.hpp"
#include "pipelines/fem_rd/element_assembly.hpp"

#include <span>
#include <string>
#include <vector>

namespace texsim::pipelines::fem_rd {

class FemAssembler {
public:
  virtual ~FemAssembler() = default;
  FemAssembler(const FemAssembler&) = delete;
  FemAssembler& operator=(const FemAssembler&) = delete;

  /// Recomputes the element geometry after the mesh moved.
  virtual void update_geometry() = 0;
  /// Values (in pattern order) of the mass matrix with per-vertex weight `weight` (empty: 1);
  /// `lumped` puts each row sum on the diagonal.
  virtual std::vector<double> mass_values(std::span<const double> weight, bool lumped) const = 0;
  /// Values of the stiffness matrix with per-vertex symmetric tensors (9 per vertex, row-major;
  /// empty: the identity, the Laplace-Beltrami operator).
  virtual std::vector<double> stiffness_values(std::span<const double> tensors) const = 0;
  /// How many local vertices a coefficient array must cover (the functions of this rank's
  /// elements): owned and ghosts for P1, the whole local mesh for Loop's wider supports.
  virtual std::int32_t coefficient_count() const = 0;
  /// The basis and this rank's elements, for the log.
  virtual std::string description() const = 0;

  /// A MATMPIAIJ matrix with this pattern and zero values. Collective.
  par::PetscMat create_matrix(const par::Comm& comm) const { return assembly_.create_matrix(comm); }
  /// Copies pattern-ordered values into `matrix` (made by create_matrix). Collective.
  void set_values(Mat matrix, const std::vector<double>& values) const {
    assembly_.set_values(matrix, values);
  }
  /// Number of stored values of this rank's rows.
  std::size_t value_count() const { return assembly_.value_count(); }

protected:
  explicit FemAssembler(ElementAssembly assembly) : assembly_(std::move(assembly)) {}
  ElementAssembly assembly_;
};

} // namespace texsim::pipelines::fem_rd
