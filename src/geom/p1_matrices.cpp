#include "geom/p1_matrices.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"

#include <Eigen/Geometry>

#include <vector>

namespace texsim::geom {
namespace {

using LocalMatrix = Eigen::Matrix3d (*)(const Vec3&, const Vec3&, const Vec3&);

Eigen::SparseMatrix<double> assemble(const TriangleMesh& mesh, LocalMatrix local) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(9 * mesh.triangles.size());
  for (const auto& tri : mesh.triangles) {
    const Eigen::Matrix3d block =
        local(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        entries.emplace_back(tri[i], tri[j], block(i, j));
      }
    }
  }
  Eigen::SparseMatrix<double> matrix(mesh.num_vertices(), mesh.num_vertices());
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

} // namespace

Eigen::Matrix3d local_mass(const Vec3& a, const Vec3& b, const Vec3& c) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Constant(1.0);
  m.diagonal().setConstant(2.0);
  return triangle_area(a, b, c) / 12.0 * m;
}

Eigen::Matrix3d local_stiffness(const Vec3& a, const Vec3& b, const Vec3& c) {
  const std::array<Vec3, 3> sides{c - b, a - c, b - a};
  const double doubled_area = sides[2].cross(-sides[1]).norm();
  TEXSIM_VERIFY(doubled_area > 0.0, "local_stiffness: triangle of zero area");
  Eigen::Matrix3d k;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      k(i, j) = sides[i].dot(sides[j]) / (2.0 * doubled_area);
    }
  }
  return k;
}

Eigen::VectorXd lumped_mass(const TriangleMesh& mesh) {
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(mesh.num_vertices());
  const auto areas = triangle_areas(mesh);
  for (std::size_t t = 0; t < areas.size(); ++t) {
    for (const auto v : mesh.triangles[t]) {
      mass[v] += areas[t] / 3.0;
    }
  }
  return mass;
}

Eigen::SparseMatrix<double> assemble_mass(const TriangleMesh& mesh) {
  return assemble(mesh, &local_mass);
}

Eigen::SparseMatrix<double> assemble_stiffness(const TriangleMesh& mesh) {
  return assemble(mesh, &local_stiffness);
}

} // namespace texsim::geom
