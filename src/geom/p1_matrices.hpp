#pragma once
/// Linear (P1) finite-element matrices on a triangle surface: the per-element 3x3 blocks that the
/// distributed FEM assembly calls, and serial global assembly for small problems and tests.
#include "geom/triangle_mesh.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace texsim::geom {

/// Exact P1 mass matrix of triangle (a, b, c): area/12 * [2 1 1; 1 2 1; 1 1 2]. Row/column i is
/// corner i. Units: model units squared.
Eigen::Matrix3d local_mass(const Vec3& a, const Vec3& b, const Vec3& c);

/// P1 stiffness (cotangent Laplacian) of triangle (a, b, c): K_ij = (e_i . e_j) / (4 area), where
/// e_i is the side opposite corner i; off-diagonal K_ij = -cot(angle at the third corner) / 2. Rows
/// sum to zero. Dimensionless. Throws texsim::Error on a triangle of zero area.
Eigen::Matrix3d local_stiffness(const Vec3& a, const Vec3& b, const Vec3& c);

/// Lumped (row-sum) mass: a third of the area of every incident triangle, per vertex.
Eigen::VectorXd lumped_mass(const TriangleMesh& mesh);

/// Global mass matrix M_ij = integral of phi_i phi_j, num_vertices square. Serial.
Eigen::SparseMatrix<double> assemble_mass(const TriangleMesh& mesh);

/// Global stiffness matrix K_ij = integral of grad phi_i . grad phi_j, num_vertices square;
/// symmetric positive semi-definite with zero row sums. Serial.
Eigen::SparseMatrix<double> assemble_stiffness(const TriangleMesh& mesh);

} // namespace texsim::geom
