#include "pipelines/fem_rd/p1_assembler.hpp"

#include "core/error.hpp"
#include "par/petsc_session.hpp"

#include <Eigen/Dense>

#include <algorithm>

namespace texsim::pipelines::fem_rd {
namespace {

// Gradients of the three barycentric (P1) functions of a triangle and its area.
struct ElementGeometry {
  std::array<Eigen::Vector3d, 3> gradient;
  double area = 0;
};

/// The element's geometry, or area 0 for a degenerate triangle.
ElementGeometry element_geometry(const geom::Vec3& x0, const geom::Vec3& x1, const geom::Vec3& x2) {
  const std::array<geom::Vec3, 3> x{x0, x1, x2};
  const geom::Vec3 normal = (x1 - x0).cross(x2 - x0);
  const double twice_area = normal.norm();
  if (!(twice_area > 0))
    return {};
  const geom::Vec3 unit_normal = normal / twice_area;
  ElementGeometry element;
  element.area = 0.5 * twice_area;
  for (int i = 0; i < 3; ++i) {
    // grad phi_i is perpendicular to the opposite edge, pointing to vertex i, of length 1/height.
    const geom::Vec3 opposite = x[(i + 2) % 3] - x[(i + 1) % 3];
    element.gradient[i] = unit_normal.cross(opposite) / twice_area;
  }
  return element;
}

/// The assembly triangles' corners as elements of three functions.
ElementAssembly p1_elements(const geom::DistributedMesh& mesh) {
  std::vector<std::int64_t> offsets{0};
  std::vector<std::int32_t> functions;
  for (const std::int32_t t : mesh.assembly_triangles()) {
    for (const std::int32_t corner : mesh.mesh().triangles[t])
      functions.push_back(mesh.global_index(corner));
    offsets.push_back(std::int64_t(functions.size()));
  }
  return {mesh.owned_begin(), mesh.owned_end(), offsets, functions};
}

} // namespace

P1Assembler::P1Assembler(const geom::DistributedMesh& mesh)
    : FemAssembler(p1_elements(mesh)), mesh_(mesh) {
  for (const std::int32_t t : mesh.assembly_triangles()) {
    const auto& tri = mesh.mesh().triangles[t];
    corners_.push_back({tri[0], tri[1], tri[2]});
  }
  update_geometry();
}

void P1Assembler::update_geometry() {
  const auto& mesh = mesh_.mesh();
  const auto& triangles = mesh_.assembly_triangles();
  areas_.resize(triangles.size());
  gradients_.resize(triangles.size());
  const auto count = std::int64_t(triangles.size());
  std::int64_t degenerate = count;
#pragma omp parallel for schedule(static) reduction(min : degenerate)
  for (std::int64_t e = 0; e < count; ++e) {
    const auto& tri = mesh.triangles[triangles[std::size_t(e)]];
    const auto element =
        element_geometry(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]);
    areas_[std::size_t(e)] = element.area;
    gradients_[std::size_t(e)] = element.gradient;
    if (!(element.area > 0))
      degenerate = std::min(degenerate, e);
  }
  TEXSIM_VERIFY(degenerate == count,
                "degenerate triangle " << triangles[std::size_t(degenerate)] << " in FEM assembly");
}

std::vector<double> P1Assembler::mass_values(std::span<const double> weight, bool lumped) const {
  std::vector<double> entries(9 * corners_.size(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t e = 0; e < corners_.size(); ++e) {
    const double area = areas_[e];
    std::array<double, 3> w{1.0, 1.0, 1.0};
    if (!weight.empty())
      for (int k = 0; k < 3; ++k)
        w[k] = weight[corners_[e][k]];
    const double sum = w[0] + w[1] + w[2];
    double* block = entries.data() + 9 * e;
    for (int i = 0; i < 3; ++i) {
      if (lumped) {
        // Row sum of the consistent matrix: int w phi_i = A/12 (w_i + sum w).
        block[3 * i + i] = area / 12.0 * (w[i] + sum);
        continue;
      }
      for (int j = 0; j < 3; ++j)
        // A/60 * sum_k w_k c_ijk with c = 6 (i=j=k), 2 (two equal), 1 (all different).
        block[3 * i + j] =
            i == j ? area / 30.0 * (2.0 * w[i] + sum) : area / 60.0 * (w[i] + w[j] + sum);
    }
  }
  return assembly_.sum_entries(entries);
}

std::vector<double> P1Assembler::stiffness_values(std::span<const double> tensors) const {
  std::vector<double> entries(9 * corners_.size(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t e = 0; e < corners_.size(); ++e) {
    const auto& gradient = gradients_[e];
    Eigen::Matrix3d mean_tensor = Eigen::Matrix3d::Identity();
    if (!tensors.empty()) {
      mean_tensor.setZero();
      for (int k = 0; k < 3; ++k)
        mean_tensor += Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
            tensors.data() + 9 * std::size_t(corners_[e][k]));
      mean_tensor /= 3.0;
    }
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d flux = mean_tensor * gradient[i];
      for (int j = 0; j < 3; ++j)
        entries[9 * e + std::size_t(3 * i + j)] = areas_[e] * flux.dot(gradient[j]);
    }
  }
  return assembly_.sum_entries(entries);
}

} // namespace texsim::pipelines::fem_rd
