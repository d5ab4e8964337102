// Wei-Levoy's mesh pyramid: level k has N / 4^k vertices and is a manifold with the surface's
// Euler characteristic; every level's bytes are the same at any rank count, with the surface on
// rank 0 alone, as on one rank; the Fig. 7 sphere (24,576 vertices) has 49,148 triangles; too many
// levels name the config keys.
#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_topology.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"
#include "support/input_error.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

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

void expect_same_bytes(const RetiledLevel& a, const RetiledLevel& b, int level) {
  ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size()) << "level " << level;
  ASSERT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size()) << "level " << level;
  EXPECT_EQ(std::memcmp(a.mesh.positions.data(), b.mesh.positions.data(),
                        a.mesh.positions.size() * sizeof(geom::Vec3)),
            0)
      << "level " << level;
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles) << "level " << level;
  // `a`'s normals are rank 0's run, `b` the serial pyramid's (all of them).
  ASSERT_LE(a.normals.size(), b.normals.size()) << "level " << level;
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
  for (int k = 0; k < 3; ++k) {
    const RetiledLevel& level = pyramid[std::size_t(k)];
    const std::int64_t count = 3072 >> (2 * k);
    ASSERT_EQ(level.mesh.num_vertices(), count) << "level " << k;
    const geom::MeshTopology topology(level.mesh);
    EXPECT_TRUE(topology.is_manifold()) << "level " << k;
    EXPECT_TRUE(topology.is_closed()) << "level " << k;
    EXPECT_EQ(topology.euler_characteristic(), 0) << "level " << k;
    ASSERT_EQ(std::int64_t(level.normals.size()), level.rank_offsets[std::size_t(world.rank) + 1] -
                                                      level.rank_offsets[std::size_t(world.rank)]);
    for (const auto& n : level.normals)
      ASSERT_NEAR(n.norm(), 1.0, 1e-12);
    ASSERT_EQ(level.rank_offsets.size(), std::size_t(world.size + 1));
    EXPECT_EQ(level.rank_offsets.front(), 0);
    EXPECT_EQ(level.rank_offsets.back(), count);
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
    for (int k = 0; k < 3; ++k)
      expect_same_bytes(pyramid[std::size_t(k)], serial[std::size_t(k)], k);
    same = ::testing::Test::HasFailure() ? 0 : 1;
  }
  MPI_Bcast(&same, 1, MPI_INT, 0, world.raw);
  EXPECT_EQ(same, 1);
}

// Wei-Levoy Fig. 7: "a sphere uniformly tesselated with 24576 vertices and 49148 faces".
TEST(MeshPyramid, Figure7SphereHas49148Triangles) {
  const auto settings = small_pyramid(24576, 1);
  const auto pyramid = build_mesh_pyramid(par::world(), geom::icosphere(5), 7, settings);
  ASSERT_EQ(pyramid.size(), 1u);
  EXPECT_EQ(pyramid[0].mesh.num_vertices(), 24576);
  EXPECT_EQ(pyramid[0].mesh.num_triangles(), 49148);
  const geom::MeshTopology topology(pyramid[0].mesh);
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
