// The Loop basis against the subdivision it is the limit of: patch values equal the limit points
// of geom::loop_subdivide at the same parameters, on regular and irregular triangles.
#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/loop_box_spline.hpp"
#include "geom/loop_patch_basis.hpp"
#include "geom/loop_subdivision.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>

namespace texsim::geom {
namespace {

/// Sum_k phi_k(s, t) x_k over the controls of triangle t.
Vec3 patch_point(const TriangleMesh& mesh, const LoopPatchBasis& basis, std::int32_t t, double s,
                 double t_param) {
  PatchBasisValues values;
  basis.evaluate(t, s, t_param, values);
  const auto controls = basis.controls(t);
  Vec3 point = Vec3::Zero();
  for (std::size_t k = 0; k < controls.size(); ++k)
    point += values.value[k] * mesh.positions[std::size_t(controls[k])];
  return point;
}

TEST(LoopPatchBasis, EqualsTheLimitOfLoopSubdivisionAtDyadicPoints) {
  // A level-1 icosphere has 20 regular triangles and 60 with a valence-5 corner; noise makes the
  // positions generic.
  const TriangleMesh coarse = noisy(icosphere(1), 0.05, 7);
  const MeshTopology topology(coarse);
  const LoopPatchBasis basis(coarse, topology);
  const int rounds = 3, n = 1 << rounds;
  const TriangleMesh fine = loop_subdivide(coarse, rounds);
  const MeshTopology fine_topology(fine);
  const LoopPatchBasis fine_basis(fine, fine_topology);
  std::vector<double> xyz;
  for (const auto& p : fine.positions)
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  std::vector<Vec3> limit(fine.positions.size());
  for (std::int32_t v = 0; v < fine.num_vertices(); ++v)
    fine_basis.limit_value(v, xyz, 3, std::span(limit[std::size_t(v)].data(), 3));

  int regular = 0, irregular = 0;
  for (std::int32_t t = 0; t < coarse.num_triangles(); ++t) {
    (basis.is_regular(t) ? regular : irregular) += 1;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const bool corner = (i == 0 && j == 0) || i == n || j == n;
        if (corner && !basis.is_regular(t))
          continue; // an extraordinary corner is never inside a regular sub-triangle
        const Vec3 point = patch_point(coarse, basis, t, double(i) / n, double(j) / n);
        double nearest = INFINITY;
        for (const auto& q : limit)
          nearest = std::min(nearest, (q - point).norm());
        ASSERT_LT(nearest, 1e-12) << "triangle " << t << " at (" << i << ", " << j << ")/" << n;
      }
  }
  EXPECT_EQ(regular, 20);
  EXPECT_EQ(irregular, 60);
}

TEST(LoopPatchBasis, PartitionOfUnityAndDerivativesOfTheValues) {
  const TriangleMesh mesh = noisy(icosphere(0), 0.05, 3); // every corner of valence 5
  const MeshTopology topology(mesh);
  const LoopPatchBasis basis(mesh, topology);
  const std::array<std::array<double, 2>, 4> points{
      {{0.2, 0.3}, {0.05, 0.01}, {0.6, 0.39}, {0.33, 0.33}}};
  const double h = 1e-6;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t)
    for (const auto& [s, u] : points) {
      PatchBasisValues at, right, up;
      basis.evaluate(t, s, u, at);
      basis.evaluate(t, s + h, u, right);
      basis.evaluate(t, s, u + h, up);
      EXPECT_EQ(at.value.size(), basis.controls(t).size());
      EXPECT_NEAR(std::accumulate(at.value.begin(), at.value.end(), 0.0), 1.0, 1e-13);
      EXPECT_NEAR(std::accumulate(at.d_s.begin(), at.d_s.end(), 0.0), 0.0, 1e-11);
      for (std::size_t k = 0; k < at.value.size(); ++k) {
        EXPECT_GE(at.value[k], -1e-15); // box splines are non-negative
        EXPECT_NEAR((right.value[k] - at.value[k]) / h, at.d_s[k], 1e-5);
        EXPECT_NEAR((up.value[k] - at.value[k]) / h, at.d_t[k], 1e-5);
      }
    }
}

TEST(LoopPatchBasis, TrianglesOfEqualStructureHaveTheSameFunctionsToTheBit) {
  // A level-1 icosphere: 20 regular triangles, and 60 with one valence-5 corner, put at a, b or
  // c by turning triangle t's corners t mod 3 times.
  TriangleMesh mesh = noisy(icosphere(1), 0.05, 5);
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    auto& corners = mesh.triangles[std::size_t(t)];
    std::rotate(corners.begin(), corners.begin() + t % 3, corners.end());
  }
  const MeshTopology topology(mesh);
  const LoopPatchBasis basis(mesh, topology);
  std::map<std::vector<std::int32_t>, std::vector<double>> values_of_class;
  std::map<std::vector<std::int32_t>, int> members;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    PatchBasisValues values;
    basis.evaluate(t, 0.15, 0.05, values); // near corner a: deep subdivision when irregular
    std::vector<double> all = values.value;
    all.insert(all.end(), values.d_s.begin(), values.d_s.end());
    all.insert(all.end(), values.d_t.begin(), values.d_t.end());
    const auto structure = basis.structure(t);
    ++members[structure];
    const auto [first, inserted] = values_of_class.emplace(structure, all);
    if (!inserted)
      EXPECT_EQ(std::memcmp(first->second.data(), all.data(), all.size() * sizeof(double)), 0)
          << "triangle " << t;
  }
  EXPECT_EQ(members.size(), 4u); // regular, and the extraordinary corner at a, b or c
  int regular = 0;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t)
    regular += basis.is_regular(t) ? 1 : 0;
  EXPECT_EQ(regular, 20);
}

TEST(LoopPatchBasis, RegularFunctionsReproduceLinearFunctions) {
  // On the lattice, sum_k phi_k (i_k, j_k) = (s, t): the box spline reproduces linear data.
  for (const auto& [s, t] :
       std::array<std::array<double, 2>, 3>{{{0.1, 0.7}, {0.5, 0.25}, {0.9, 0.05}}}) {
    const auto basis = regular_patch_basis(s, t);
    double x = 0, y = 0;
    for (std::size_t k = 0; k < 12; ++k) {
      x += basis.value[k] * kRegularPatchLattice[k][0];
      y += basis.value[k] * kRegularPatchLattice[k][1];
    }
    EXPECT_NEAR(x, s, 1e-14);
    EXPECT_NEAR(y, t, 1e-14);
  }
}

TEST(LoopPatchBasis, TrianglesAtABoundaryAreNotEvaluable) {
  const TriangleMesh mesh = plane(Vec3(1, 1, 0), 6);
  const MeshTopology topology(mesh);
  const LoopPatchBasis basis(mesh, topology);
  int evaluable = 0;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t)
    if (basis.evaluable(t))
      ++evaluable;
    else
      EXPECT_THROW((void)basis.controls(t), texsim::Error);
  // The triangles whose corners all lie inside the 7 x 7 grid of vertices: those of the inner
  // 4 x 4 cells, two per cell.
  EXPECT_EQ(evaluable, 2 * 4 * 4);
}

} // namespace
} // namespace texsim::geom
