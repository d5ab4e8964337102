// Wei-Levoy's mesh pyramid: level k has N / 4^k vertices and is a manifold with the surface's
// Euler characteristic; every level's bytes are the same at any rank count, with the surface on
// rank 0 alone, as on one rank; each rank holds its run and a share of the triangles, and its
// star is exactly the triangles around its run; the Fig. 7 sphere (24,576 vertices) has 49,148
// triangles; too many levels name the config keys.
#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_topology.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"
#include "pipelines/surface_synthesis/run_star.hpp"
#include "support/input_error.hpp"
#include "whole_level.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

namespace texsim::pipelines::surface_synthesis {
namespace {

par::Comm self() {
  par::Comm comm;
  comm.raw = MPI_COMM_SELF;
  return comm;
}

MeshPyramidSettings small_pyramid(std::int64_t finest, int levels) {
  MeshPyramidSettings settings;
  settings.finest_count = finest;
  settings.levels = levels;
  settings.cells.relaxation.iterations = 8;
  return settings;
}

/// A level as the tests compare it: its whole mesh and every run's normals, on every rank.
struct WholeLevel {
  geom::TriangleMesh mesh;
  std::vector<geom::Vec3> normals;
  double spacing;

  WholeLevel(const par::Comm& comm, const RetiledLevel& level)
      : mesh(whole_level_mesh(comm, level)), normals(whole_runs(comm, level, level.normals)),
        spacing(level.spacing) {}
};

void expect_same_bytes(const WholeLevel& a, const WholeLevel& b, int level) {
  ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size()) << "level " << level;
  ASSERT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size()) << "level " << level;
  EXPECT_EQ(std::memcmp(a.mesh.positions.data(), b.mesh.positions.data(),
                        a.mesh.positions.size() * sizeof(geom::Vec3)),
            0)
      << "level " << level;
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles) << "level " << level;
  ASSERT_EQ(a.normals.size(), b.normals.size()) << "level " << level;
  EXPECT_EQ(std::memcmp(a.normals.data(), b.normals.data(), a.normals.size() * sizeof(geom::Vec3)),
            0)
      << "level " << level;
  EXPECT_EQ(std::memcmp(&a.spacing, &b.spacing, sizeof(double)), 0) << "level " << level;
}

TEST(MeshPyramid, LevelsQuarterTheVerticesStayManifoldAndMatchOneRank) {
  const par::Comm world = par::world();
  const geom::TriangleMesh ring = geom::torus(1.0, 0.45, 64, 28);
  const auto settings = small_pyramid(3072, 3);
  // Only rank 0 holds the surface: the others pass an empty mesh.
  const auto pyramid =
      build_mesh_pyramid(world, world.is_root() ? ring : geom::TriangleMesh{}, 21, settings);
  ASSERT_EQ(pyramid.size(), 3u);
  std::vector<WholeLevel> wholes;
  for (int k = 0; k < 3; ++k) {
    const RetiledLevel& level = pyramid[std::size_t(k)];
    const std::int64_t count = 3072 >> (2 * k);
    wholes.emplace_back(world, level);
    const geom::TriangleMesh& mesh = wholes.back().mesh;
    ASSERT_EQ(level.vertex_count(), count) << "level " << k;
    ASSERT_EQ(mesh.num_vertices(), count) << "level " << k;
    EXPECT_EQ(level.triangle_count(), mesh.num_triangles()) << "level " << k;
    const geom::MeshTopology topology(mesh);
    EXPECT_TRUE(topology.is_manifold()) << "level " << k;
    EXPECT_TRUE(topology.is_closed()) << "level " << k;
    EXPECT_EQ(topology.euler_characteristic(), 0) << "level " << k;
    ASSERT_EQ(level.rank_offsets.size(), std::size_t(world.size + 1));
    EXPECT_EQ(level.rank_offsets.front(), 0);
    EXPECT_EQ(level.rank_offsets.back(), count);
    // A rank holds its run's positions and normals and a share of the triangles, which
    // together hold each triangle once.
    const std::int64_t run = level.run_begin(world.rank + 1) - level.run_begin(world.rank);
    ASSERT_EQ(std::int64_t(level.positions.size()), run) << "level " << k;
    ASSERT_EQ(std::int64_t(level.normals.size()), run) << "level " << k;
    std::int64_t shares = std::int64_t(level.triangles.owned_count());
    MPI_Allreduce(MPI_IN_PLACE, &shares, 1, MPI_INT64_T, MPI_SUM, world.raw);
    EXPECT_EQ(shares, level.triangle_count()) << "level " << k;
    if (world.size > 1) {
      EXPECT_LT(std::int64_t(level.triangles.owned_count()), level.triangle_count());
    }
    for (const auto& n : level.normals)
      ASSERT_NEAR(n.norm(), 1.0, 1e-12);
    // d_L^2 / 2 is the mean triangle area: the torus's area over 2 V triangles, within the
    // retiling's chordal shrinkage.
    const double torus_area = 4 * std::numbers::pi * std::numbers::pi * 1.0 * 0.45;
    EXPECT_NEAR(level.spacing * level.spacing / 2 / (torus_area / double(2 * count)), 1.0, 0.05)
        << "level " << k;
  }
  // The same bytes as one rank computes (rank 0 computes it alone; the verdict is shared).
  int same = 1;
  if (world.is_root()) {
    const auto serial = build_mesh_pyramid(self(), ring, 21, settings);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(pyramid[std::size_t(k)].mesh_hash, serial[std::size_t(k)].mesh_hash);
      expect_same_bytes(wholes[std::size_t(k)], WholeLevel(self(), serial[std::size_t(k)]), k);
    }
    same = ::testing::Test::HasFailure() ? 0 : 1;
  }
  MPI_Bcast(&same, 1, MPI_INT, 0, world.raw);
  EXPECT_EQ(same, 1);
}

// A rank's star is exactly the level's triangles with a corner in its run, and its 1-rings are
// the whole level's.
TEST(MeshPyramid, RunStarIsTheTrianglesAroundTheRun) {
  const par::Comm world = par::world();
  const auto pyramid = build_mesh_pyramid(world, geom::icosphere(4), 3, small_pyramid(1536, 1));
  const RetiledLevel& level = pyramid.front();
  const geom::TriangleMesh whole = whole_level_mesh(world, level);
  const std::int64_t first = level.run_begin(world.rank);
  const std::int64_t end = level.run_begin(world.rank + 1);
  std::vector<std::int64_t> expected_ids;
  std::vector<std::array<std::int64_t, 3>> expected_corners;
  for (std::size_t t = 0; t < whole.triangles.size(); ++t) {
    const auto& c = whole.triangles[t];
    if (std::any_of(c.begin(), c.end(), [&](std::int32_t v) { return v >= first && v < end; })) {
      expected_ids.push_back(std::int64_t(t));
      expected_corners.push_back({c[0], c[1], c[2]});
    }
  }
  const geom::LocalSurface& star = level.star;
  EXPECT_EQ(star.triangle_ids, expected_ids);
  std::vector<std::array<std::int64_t, 3>> corners;
  for (const auto& c : star.mesh.triangles)
    corners.push_back({star.vertex_ids[std::size_t(c[0])], star.vertex_ids[std::size_t(c[1])],
                       star.vertex_ids[std::size_t(c[2])]});
  EXPECT_EQ(corners, expected_corners);
  for (std::size_t v = 0; v < star.vertex_ids.size(); ++v)
    ASSERT_EQ(std::memcmp(&star.mesh.positions[v],
                          &whole.positions[std::size_t(star.vertex_ids[v])], sizeof(geom::Vec3)),
              0);
  const auto rings = run_rings(star, first, end - first);
  const auto whole_rings = run_rings(whole, first, end - first);
  EXPECT_EQ(rings.offsets, whole_rings.offsets);
  EXPECT_EQ(rings.indices, whole_rings.indices);
  if (world.size > 1) {
    EXPECT_LT(star.mesh.num_triangles(), whole.num_triangles());
  }
}

// Wei-Levoy Fig. 7: "a sphere uniformly tesselated with 24576 vertices and 49148 faces".
TEST(MeshPyramid, Figure7SphereHas49148Triangles) {
  const auto settings = small_pyramid(24576, 1);
  const auto pyramid = build_mesh_pyramid(par::world(), geom::icosphere(5), 7, settings);
  ASSERT_EQ(pyramid.size(), 1u);
  EXPECT_EQ(pyramid[0].vertex_count(), 24576);
  EXPECT_EQ(pyramid[0].triangle_count(), 49148);
  const geom::MeshTopology topology(whole_level_mesh(par::world(), pyramid[0]));
  EXPECT_TRUE(topology.is_manifold());
  EXPECT_EQ(topology.euler_characteristic(), 2);
}

TEST(MeshPyramid, TooFewVerticesNameTheLevelAndTheKeys) {
  const geom::TriangleMesh sphere = geom::icosphere(3);
  const std::string levels = test::input_error_message(
      [&] { build_mesh_pyramid(par::world(), sphere, 1, small_pyramid(100, 3)); });
  EXPECT_NE(levels.find("surface_synthesis.levels"), std::string::npos) << levels;
  EXPECT_NE(levels.find("6 on the coarsest level"), std::string::npos) << levels;

  // A thin torus with a handful of vertices cannot be retiled into a torus.
  const geom::TriangleMesh ring = geom::torus(1.0, 0.1, 48, 12);
  const std::string thin = test::input_error_message(
      [&] { build_mesh_pyramid(par::world(), ring, 1, small_pyramid(40, 1)); });
  EXPECT_NE(thin.find("surface_synthesis.vertices"), std::string::npos) << thin;
  EXPECT_NE(thin.find("level 0 of 1 (40 vertices)"), std::string::npos) << thin;
}

} // namespace
} // namespace texsim::pipelines::surface_synthesis
