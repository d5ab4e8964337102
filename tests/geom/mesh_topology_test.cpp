#include "geom/generators.hpp"
#include "geom/mesh_topology.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace texsim::geom {
namespace {

TriangleMesh quad() {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TEST(MeshTopology, QuadEdgesIncidencesAndBoundary) {
  const MeshTopology topo(quad());
  ASSERT_EQ(topo.num_edges(), 5);
  const std::vector<Edge> expected{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {2, 3}};
  EXPECT_EQ(topo.edges(), expected);
  const auto diagonal = topo.find_edge(2, 0);
  ASSERT_EQ(diagonal, 1);
  EXPECT_EQ(std::vector<std::int32_t>(topo.edge_triangles(diagonal).begin(),
                                      topo.edge_triangles(diagonal).end()),
            (std::vector<std::int32_t>{0, 1}));
  EXPECT_EQ(topo.find_edge(1, 3), -1);
  // Edge i of a triangle is opposite corner i.
  EXPECT_EQ(topo.edges()[topo.triangle_edges(0)[0]], (Edge{1, 2}));
  EXPECT_EQ(topo.edges()[topo.triangle_edges(0)[1]], (Edge{0, 2}));
  EXPECT_EQ(topo.edges()[topo.triangle_edges(0)[2]], (Edge{0, 1}));
  const auto n0 = topo.vertex_neighbors().row(0);
  EXPECT_EQ(std::vector<std::int32_t>(n0.begin(), n0.end()), (std::vector<std::int32_t>{1, 2, 3}));
  const auto t2 = topo.vertex_triangles().row(2);
  EXPECT_EQ(std::vector<std::int32_t>(t2.begin(), t2.end()), (std::vector<std::int32_t>{0, 1}));
  EXPECT_EQ(topo.boundary_edges().size(), 4u);
  EXPECT_EQ(topo.boundary_vertices(), (std::vector<std::int32_t>{0, 1, 2, 3}));
  EXPECT_FALSE(topo.is_closed());
  EXPECT_TRUE(topo.is_manifold());
  EXPECT_EQ(topo.euler_characteristic(), 1);
}

TEST(MeshTopology, EdgesAreTheSortedDistinctSidesOfAnyMesh) {
  // Against a brute-force reference: a sphere in shuffled vertex order, plus a fan of 60
  // triangles around one hub vertex (a bucket too large for insertion), a repeated triangle and
  // a degenerate one. Edges are the distinct sides in increasing (smaller, larger) order, and
  // each edge lists its triangles in increasing order.
  TriangleMesh mesh = icosphere(2);
  const std::int32_t n = mesh.num_vertices();
  for (auto& tri : mesh.triangles)
    for (auto& v : tri)
      v = (v * 37 + 11) % n; // 37 is prime to n = 162: a permutation
  const std::int32_t hub = n;
  mesh.positions.resize(std::size_t(n) + 1 + 60);
  for (std::int32_t k = 0; k < 60; ++k)
    mesh.triangles.push_back({hub, n + 1 + k, n + 1 + (k + 1) % 60});
  mesh.triangles.push_back(mesh.triangles[5]);
  mesh.triangles.push_back({3, 3, 7});
  const MeshTopology topo(mesh);

  std::set<std::pair<std::int32_t, std::int32_t>> sides;
  for (const auto& tri : mesh.triangles)
    for (int c = 0; c < 3; ++c) {
      const auto a = tri[(c + 1) % 3], b = tri[(c + 2) % 3];
      sides.insert({std::min(a, b), std::max(a, b)});
    }
  ASSERT_EQ(std::size_t(topo.num_edges()), sides.size());
  std::size_t e = 0;
  for (const auto& [a, b] : sides) {
    EXPECT_EQ(topo.edges()[e], (Edge{a, b})) << e;
    std::vector<std::int32_t> expected;
    for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
      const auto& tri = mesh.triangles[t];
      for (int c = 0; c < 3; ++c)
        if (std::min(tri[(c + 1) % 3], tri[(c + 2) % 3]) == a &&
            std::max(tri[(c + 1) % 3], tri[(c + 2) % 3]) == b) {
          EXPECT_EQ(topo.triangle_edges(t)[c], std::int32_t(e));
          if (expected.empty() || expected.back() != t)
            expected.push_back(t);
        }
    }
    const auto listed = topo.edge_triangles(std::int32_t(e));
    EXPECT_EQ(std::vector<std::int32_t>(listed.begin(), listed.end()), expected) << e;
    ++e;
  }
}

TEST(MeshTopology, ClosedSphereEveryEdgeHasTwoTriangles) {
  const auto mesh = icosphere(3);
  const MeshTopology topo(mesh);
  EXPECT_EQ(topo.num_edges(), 3 * mesh.num_triangles() / 2);
  for (std::int32_t e = 0; e < topo.num_edges(); ++e) {
    ASSERT_EQ(topo.edge_triangles(e).size(), 2u) << "edge " << e;
    for (const auto t : topo.edge_triangles(e)) {
      const auto& tri = mesh.triangles[t];
      EXPECT_NE(std::find(tri.begin(), tri.end(), topo.edges()[e][0]), tri.end());
      EXPECT_NE(std::find(tri.begin(), tri.end(), topo.edges()[e][1]), tri.end());
    }
  }
  EXPECT_EQ(topo.euler_characteristic(), 2);
  EXPECT_TRUE(topo.is_closed());
  EXPECT_TRUE(topo.is_manifold());
  EXPECT_TRUE(topo.isolated_vertices().empty());
  // On a closed manifold a vertex has as many neighbours as triangles; rows are sorted and
  // symmetric.
  for (std::int32_t v = 0; v < topo.num_vertices(); ++v) {
    const auto neighbors = topo.vertex_neighbors().row(v);
    ASSERT_EQ(neighbors.size(), topo.vertex_triangles().row(v).size());
    ASSERT_TRUE(std::is_sorted(neighbors.begin(), neighbors.end()));
    for (const auto w : neighbors) {
      const auto back = topo.vertex_neighbors().row(w);
      ASSERT_TRUE(std::binary_search(back.begin(), back.end(), v));
      ASSERT_GE(topo.find_edge(v, w), 0);
    }
  }
}

TEST(MeshTopology, TorusHasEulerCharacteristicZero) {
  const MeshTopology topo(torus(2.0, 0.5, 24, 12));
  EXPECT_EQ(topo.euler_characteristic(), 0);
  EXPECT_TRUE(topo.is_closed());
  EXPECT_TRUE(topo.is_manifold());
}

TEST(MeshTopology, FindsNonManifoldEdgesAndVertices) {
  TriangleMesh fin; // three triangles on edge 0-1
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshTopology fin_topo(fin);
  ASSERT_EQ(fin_topo.non_manifold_edges().size(), 1u);
  EXPECT_EQ(fin_topo.edges()[fin_topo.non_manifold_edges()[0]], (Edge{0, 1}));
  EXPECT_FALSE(fin_topo.is_manifold());

  TriangleMesh bowtie; // two triangles touching at vertex 0 only, plus an isolated vertex 5
  bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}, {9, 9, 9}};
  bowtie.triangles = {{0, 1, 2}, {0, 3, 4}};
  const MeshTopology bowtie_topo(bowtie);
  EXPECT_TRUE(bowtie_topo.non_manifold_edges().empty());
  EXPECT_EQ(bowtie_topo.non_manifold_vertices(), (std::vector<std::int32_t>{0}));
  EXPECT_EQ(bowtie_topo.isolated_vertices(), (std::vector<std::int32_t>{5}));
  EXPECT_FALSE(bowtie_topo.is_manifold());
}

} // namespace
} // namespace texsim::geom
