// The Loop basis against the subdivision it is the limit of: patch values equal the limit points
// of geom::loop_subdivide at the same parameters, on regular and irregular triangles and at
// boundaries.
#include "core/error.hpp"
#include "geom/crease_edges.hpp"
#include "geom/generators.hpp"
#include "geom/loop_box_spline.hpp"
#include "geom/loop_patch_basis.hpp"
#include "geom/loop_subdivision.hpp"
#include "geom/patch_refinement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <set>

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

/// The limit points of `fine`'s vertices that lie on triangles (Loop's limit masks, with the
/// crease rules on `creases`).
std::vector<Vec3> limit_points(const TriangleMesh& fine, std::span<const char> creases = {}) {
  const MeshTopology topology(fine);
  const LoopPatchBasis basis(fine, topology, creases);
  std::vector<double> xyz;
  for (const auto& p : fine.positions)
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  std::vector<Vec3> limit;
  for (std::int32_t v = 0; v < fine.num_vertices(); ++v)
    if (!topology.vertex_triangles().row(v).empty()) {
      limit.emplace_back();
      basis.limit_value(v, xyz, 3, std::span(limit.back().data(), 3));
    }
  return limit;
}

/// Expects the basis of `coarse` to give one of `limit` (to 1e-12) at every dyadic point of step
/// 1/n of every triangle, with values summing to 1, except on the edges `sharp(a, b)` flags and
/// at irregular triangles' corners, which no regular sub-triangle contains. Returns the number
/// of points checked (stops at the first miss).
template <class SharpEdge>
int expect_limit_points_off_sharp_edges(const TriangleMesh& coarse, const LoopPatchBasis& basis,
                                        const std::vector<Vec3>& limit, int n, SharpEdge sharp) {
  int points = 0;
  for (std::int32_t t = 0; t < coarse.num_triangles(); ++t) {
    if (!basis.evaluable(t)) {
      ADD_FAILURE() << "triangle " << t << " is not evaluable";
      return points;
    }
    const auto [a, b, c] = coarse.triangles[std::size_t(t)];
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const bool corner = (i == 0 && j == 0) || i == n || j == n;
        if ((corner && !basis.is_regular(t)) || (j == 0 && sharp(a, b)) ||
            (i + j == n && sharp(b, c)) || (i == 0 && sharp(c, a)))
          continue;
        PatchBasisValues values;
        basis.evaluate(t, double(i) / n, double(j) / n, values);
        EXPECT_NEAR(std::accumulate(values.value.begin(), values.value.end(), 0.0), 1.0, 1e-13);
        const Vec3 point = patch_point(coarse, basis, t, double(i) / n, double(j) / n);
        double nearest = INFINITY;
        for (const auto& q : limit)
          nearest = std::min(nearest, (q - point).norm());
        if (nearest >= 1e-12) {
          ADD_FAILURE() << "triangle " << t << " at (" << i << ", " << j << ")/" << n << ": "
                        << nearest << " from the nearest limit point";
          return points;
        }
        ++points;
      }
  }
  return points;
}

TEST(LoopPatchBasis, EqualsTheLimitOfLoopSubdivisionAtDyadicPoints) {
  // A level-1 icosphere has 20 regular triangles and 60 with a valence-5 corner; noise makes the
  // positions generic.
  const TriangleMesh coarse = noisy(icosphere(1), 0.05, 7);
  const MeshTopology topology(coarse);
  const LoopPatchBasis basis(coarse, topology);
  const int rounds = 3, n = 1 << rounds;
  const std::vector<Vec3> limit = limit_points(loop_subdivide(coarse, rounds));

  int regular = 0;
  for (std::int32_t t = 0; t < coarse.num_triangles(); ++t)
    regular += basis.is_regular(t);
  const auto no_sharp_edges = [](std::int32_t, std::int32_t) { return false; };
  const int points = expect_limit_points_off_sharp_edges(coarse, basis, limit, n, no_sharp_edges);
  // Every lattice point but the 3 corners of each of the 60 irregular triangles.
  EXPECT_EQ(points, 80 * (n + 1) * (n + 2) / 2 - 60 * 3);
  const int irregular = coarse.num_triangles() - regular;
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
    if (!inserted) {
      EXPECT_EQ(std::memcmp(first->second.data(), all.data(), all.size() * sizeof(double)), 0)
          << "triangle " << t;
    }
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

/// A level-1 icosphere without vertex 0's star (a pentagonal hole; vertex 0 is left unused), made
/// generic by noise: boundary vertices of 4 and 5 triangles, interior ones of valence 5 and 6.
TriangleMesh sphere_with_a_hole() {
  TriangleMesh mesh = noisy(icosphere(1), 0.05, 11);
  std::erase_if(mesh.triangles,
                [](const auto& tri) { return std::find(tri.begin(), tri.end(), 0) != tri.end(); });
  return mesh;
}

TEST(LoopPatchBasis, BoundaryRulesEqualTheLimitOfLoopSubdivisionAtDyadicPoints) {
  // loop_subdivide refines boundaries with the boundary masks (midpoints, (b1 + 6 v + b2) / 8),
  // and the limit of a boundary vertex is (b1 + 4 v + b2) / 6: the basis must give those limit
  // points on the triangles at the hole too, at every dyadic point off the boundary.
  for (const TriangleMesh& coarse :
       {sphere_with_a_hole(), noisy(plane(Vec3(1, 1, 0), 3), 0.04, 2)}) {
    const MeshTopology topology(coarse);
    const LoopPatchBasis basis(coarse, topology);
    const int rounds = 3, n = 1 << rounds;
    const std::vector<Vec3> limit = limit_points(loop_subdivide(coarse, rounds));
    std::set<std::pair<std::int32_t, std::int32_t>> boundary;
    for (const std::int32_t e : topology.boundary_edges())
      boundary.insert(std::minmax(topology.edges()[e][0], topology.edges()[e][1]));
    ASSERT_FALSE(boundary.empty());
    const auto on_boundary = [&](std::int32_t a, std::int32_t b) {
      return boundary.count(std::minmax(a, b)) > 0;
    };
    int at_boundary = 0;
    for (const auto& triangle : coarse.triangles)
      at_boundary += std::any_of(triangle.begin(), triangle.end(), [&](std::int32_t v) {
        return std::any_of(boundary.begin(), boundary.end(),
                           [&](const auto& edge) { return edge.first == v || edge.second == v; });
      });
    const int points = expect_limit_points_off_sharp_edges(coarse, basis, limit, n, on_boundary);
    EXPECT_GT(at_boundary, 4);
    EXPECT_GT(points, 30 * coarse.num_triangles());
  }
}

/// A square of 8 x 8 cells folded along its middle column of vertices: x <= 0 lies in the plane
/// z = 0, the other half in the plane x = 0 (a 90 degree crease along the y axis).
TriangleMesh folded_square() {
  TriangleMesh mesh = plane(Vec3(2, 1, 0), 8);
  for (auto& p : mesh.positions) {
    const double u = p.x() - 1.0;
    p = u <= 0 ? Vec3(u, p.y(), 0) : Vec3(0, p.y(), u);
  }
  return mesh;
}

TEST(LoopPatchBasis, CreaseRulesKeepAFoldSharp) {
  // With the fold's edges as creases each half's limit surface stays in its plane: the masks
  // of a half read only its own vertices and the crease's, which lie in both planes. Without
  // crease rules the limit surface rounds the fold.
  const TriangleMesh mesh = folded_square();
  const MeshTopology topology(mesh);
  const std::vector<char> creases = crease_edges(mesh, topology, 45.0);
  EXPECT_EQ(std::count(creases.begin(), creases.end(), 1), 8); // the fold's 8 edges
  const LoopPatchBasis sharp(mesh, topology, creases), smooth(mesh, topology);
  const int n = 8;
  double sharp_off_plane = 0, smooth_off_plane = 0;
  int points = 0;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& tri = mesh.triangles[std::size_t(t)];
    // The right half has x = 0 at every vertex; a left triangle has a vertex at x < 0.
    const bool left = std::any_of(tri.begin(), tri.end(),
                                  [&](std::int32_t v) { return mesh.positions[v].x() < 0; });
    const auto sharp_edge = [&](std::int32_t a, std::int32_t b) {
      const std::int32_t e = topology.find_edge(a, b);
      return creases[std::size_t(e)] || topology.edge_triangles(e).size() == 1;
    };
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const bool corner = (i == 0 && j == 0) || i == n || j == n;
        if (corner || (j == 0 && sharp_edge(tri[0], tri[1])) ||
            (i + j == n && sharp_edge(tri[1], tri[2])) || (i == 0 && sharp_edge(tri[2], tri[0])))
          continue; // never inside a regular sub-triangle
        const double s = double(i) / n, u = double(j) / n;
        PatchBasisValues values;
        sharp.evaluate(t, s, u, values);
        EXPECT_NEAR(std::accumulate(values.value.begin(), values.value.end(), 0.0), 1.0, 1e-13);
        const Vec3 kept = patch_point(mesh, sharp, t, s, u);
        const Vec3 rounded = patch_point(mesh, smooth, t, s, u);
        sharp_off_plane = std::max(sharp_off_plane, std::abs(left ? kept.z() : kept.x()));
        smooth_off_plane = std::max(smooth_off_plane, std::abs(left ? rounded.z() : rounded.x()));
        ++points;
      }
  }
  EXPECT_GT(points, 1000);
  EXPECT_LT(sharp_off_plane, 1e-12);
  EXPECT_GT(smooth_off_plane, 1e-2);
  // Crease classes get tables of their own: the structure names the creases.
  const std::int32_t at_fold = 6; // cell (3, 0): its right edge lies on the fold
  EXPECT_NE(sharp.structure(at_fold), smooth.structure(at_fold));

  // geom::refine keeps the fold too: every fine vertex stays in one of the planes, and the
  // fold's ends (two boundary edges and a crease: corners) do not move.
  const std::vector<RefinementStep> rounds(3);
  const auto off_planes = [](const TriangleMesh& fine) {
    double most = 0;
    for (const auto& p : fine.positions)
      most = std::max(most, std::min(std::abs(p.x()), std::abs(p.z())));
    return most;
  };
  const TriangleMesh refined_sharp = refine(mesh, rounds, creases);
  EXPECT_LT(off_planes(refined_sharp), 1e-15);
  EXPECT_GT(off_planes(refine(mesh, rounds)), 1e-2);
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.positions[v].x() == 0 && mesh.positions[v].z() == 0 &&
        (mesh.positions[v].y() == 0 || mesh.positions[v].y() == 1)) {
      EXPECT_EQ(refined_sharp.positions[v], mesh.positions[v]) << "fold end " << v;
    }
}

TEST(LoopPatchBasis, CreaseRulesEqualTheLimitOfCreasedLoopSubdivisionAtDyadicPoints) {
  // A noisy cube: its 12 edges are creases meeting at 8 corners, and one more crease edge inside
  // a face makes two darts. geom::refine keeps the creases through its rounds (their halves are
  // creases again); the basis must give that subdivision's limit points at every dyadic point
  // off the sharp edges.
  const TriangleMesh coarse = noisy(box(Vec3(1, 1, 1), 3), 0.03, 4);
  const MeshTopology topology(coarse);
  std::vector<char> creases = crease_edges(coarse, topology, 45.0);
  ASSERT_EQ(std::count(creases.begin(), creases.end(), 1), 36);
  const auto touches_a_crease = [&](std::int32_t v) {
    const auto ring = topology.vertex_neighbors().row(v);
    return std::any_of(ring.begin(), ring.end(),
                       [&](std::int32_t w) { return creases[topology.find_edge(v, w)] != 0; });
  };
  std::int32_t dart = 0;
  while (touches_a_crease(topology.edges()[dart][0]) || touches_a_crease(topology.edges()[dart][1]))
    ++dart;
  creases[std::size_t(dart)] = 1;

  const LoopPatchBasis basis(coarse, topology, creases);
  const int rounds = 3, n = 1 << rounds;
  std::vector<char> fine_creases;
  const TriangleMesh fine =
      refine(coarse, std::vector<RefinementStep>(rounds), creases, &fine_creases);
  ASSERT_EQ(std::count(fine_creases.begin(), fine_creases.end(), 1), 37 * n);
  const std::vector<Vec3> limit = limit_points(fine, fine_creases);
  const auto sharp = [&](std::int32_t a, std::int32_t b) {
    return creases[std::size_t(topology.find_edge(a, b))] != 0;
  };
  const int points = expect_limit_points_off_sharp_edges(coarse, basis, limit, n, sharp);
  EXPECT_GT(points, 30 * coarse.num_triangles());
}

TEST(LoopPatchBasis, VerticesOfTwoFansAreNotEvaluable) {
  // Two triangles that share only vertex 0 (a bowtie): no Loop mask applies there.
  TriangleMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0), Vec3(-1, -1, 0)};
  mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
  const MeshTopology topology(mesh);
  const LoopPatchBasis basis(mesh, topology);
  for (std::int32_t t = 0; t < 2; ++t) {
    EXPECT_FALSE(basis.evaluable(t));
    EXPECT_THROW((void)basis.controls(t), texsim::Error);
  }
  const std::vector<double> values{1, 2, 3, 4, 5};
  double out = 0;
  EXPECT_THROW(basis.limit_value(0, values, 1, std::span(&out, 1)), texsim::Error);
}

} // namespace
} // namespace texsim::geom
