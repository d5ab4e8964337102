#pragma once
/// fem_rd's matrices in the paper's own basis (Bajaj, Zhang, Xu, eq. 7 and section 3.3): Loop's
/// C1 box-spline functions with the mesh as control mesh, integrated on the limit surface
/// x = sum_k x_k phi_k by Gauss quadrature.
///
/// A triangle's functions are its controls (geom::LoopPatchBasis): 12 on a regular triangle,
/// whose values at the quadrature points are the same for every regular triangle and kept once;
/// the corners' 1-rings on an irregular one, evaluated by subdivision down to a regular
/// sub-triangle and kept per triangle, as the paper does for its few irregular patches. Regular
/// triangles take a collapsed 4 x 4 Gauss-Legendre rule (exact to degree 7 in s, t); an
/// irregular triangle the same rule on each of its 4 sub-triangles, closer to the pieces its
/// functions are smooth on.
///
/// A rank's elements are the triangles within one ring of its owned vertices (every triangle
/// whose controls include an owned vertex); their controls reach three rings out, which
/// DistributedMesh's halo holds. Coefficient arrays cover the whole local mesh
/// (coefficient_count). The surface must be closed (no boundary edges).
#include "geom/distributed_mesh.hpp"
#include "geom/loop_patch_basis.hpp"
#include "pipelines/fem_rd/fem_assembler.hpp"

#include <Eigen/Core>

#include <array>
#include <span>
#include <vector>

namespace texsim::pipelines::fem_rd {

class LoopAssembler final : public FemAssembler {
public:
  /// Builds the pattern, the basis values at every quadrature point and the geometry of the
  /// current control positions, with the crease rules on the mesh's creases
  /// (DistributedMesh::creases). Not collective.
  explicit LoopAssembler(const geom::DistributedMesh& mesh);

  /// Recomputes the limit surface's tangents and area element at every quadrature point.
  void update_geometry() override;
  std::vector<double> mass_values(std::span<const double> weight, bool lumped) const override;
  std::vector<double> stiffness_values(std::span<const double> tensors) const override;
  std::int32_t coefficient_count() const override { return mesh_.mesh().num_vertices(); }
  std::string description() const override;

  /// Elements of this rank, how many of them are irregular and in how many classes of equal
  /// structure (for the log).
  std::size_t element_count() const { return elements_.size(); }
  std::size_t irregular_count() const;
  std::size_t irregular_class_count() const { return tables_.size() - 1; }

private:
  /// Quadrature points of a regular triangle (the collapsed 4 x 4 Gauss rule).
  static constexpr int kRegularPoints = 16;

  /// The elements (triangles within one ring of an owned vertex) and their controls.
  struct ElementList {
    std::vector<std::int32_t> triangles;
    std::vector<std::int64_t> offsets{0};
    std::vector<std::int32_t> controls; ///< local vertex ids
  };
  static ElementList list_elements(const geom::DistributedMesh& mesh);
  LoopAssembler(const geom::DistributedMesh& mesh, ElementList list);

  /// The functions of an element's controls at its quadrature points (rows: points).
  struct Table {
    std::vector<double> weight; ///< quadrature weight in the (s, t) parameter plane
    Eigen::MatrixXd value, d_s, d_t;
  };
  struct Element {
    std::int32_t triangle = 0; ///< local triangle
    std::size_t table = 0;     ///< tables_[0] is the regular one
    std::size_t first_control = 0;
    std::size_t first_point = 0; ///< into the per-point geometry
  };

  /// The functions of triangle t's controls at the given points of the parameter triangle.
  static Table irregular_table(const geom::LoopPatchBasis& basis, std::int32_t t,
                               const std::vector<std::array<double, 2>>& points,
                               const std::vector<double>& weights);

  const geom::DistributedMesh& mesh_;
  std::vector<Table> tables_; ///< [0] regular, then one per class of irregular triangles
  std::vector<Element> elements_;
  std::vector<std::int32_t> controls_; ///< local vertex ids, element after element
  /// Per quadrature point: weight times the area element, and the dual tangents a^s, a^t
  /// (surface gradient of f = f_s a^s + f_t a^t).
  std::vector<double> measure_;
  std::vector<Eigen::Vector3d> dual_s_, dual_t_;

  std::size_t control_count(const Element& e) const {
    return std::size_t(tables_[e.table].value.cols());
  }
};

} // namespace texsim::pipelines::fem_rd
