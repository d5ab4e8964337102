// The mesh section's crease_angle: edges flagged on the surface before subdivision stay sharp
// through the serial rounds, the rounds left to the ranks' parts, and the corners where three
// meet; a box keeps its faces flat. A bad angle names its key.
#include "core/config.hpp"
#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_source.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace texsim::geom {
namespace {

MeshSource source_of(const std::string& mesh_yaml) {
  auto document = ConfigDocument::parse("mesh: " + mesh_yaml, "test.yaml");
  return read_mesh_source(document.root().section("mesh"));
}

/// Farthest distance of a vertex from the surface of the box [-1/2, 1/2]^3 (its vertices inside).
double off_the_unit_box(const TriangleMesh& mesh) {
  double most = 0;
  for (const auto& p : mesh.positions) {
    double nearest_face = INFINITY;
    for (int axis = 0; axis < 3; ++axis)
      nearest_face = std::min(nearest_face, 0.5 - std::abs(p[axis]));
    most = std::max(most, std::abs(nearest_face));
  }
  return most;
}

TEST(MeshSource, CreaseAngleKeepsABoxFlatThroughSubdivision) {
  const std::string box = "{generator: box, cells_per_edge: 3, subdivision_levels: 2";
  std::vector<char> creases;
  const TriangleMesh sharp =
      build_mesh(source_of(box + ", crease_angle: 45}"), 1, nullptr, &creases);
  EXPECT_LT(off_the_unit_box(sharp), 1e-15);
  // The 12 box edges, 3 coarse edges each, halved twice; the 8 corners do not move.
  EXPECT_EQ(std::count(creases.begin(), creases.end(), 1), 12 * 3 * 4);
  const TriangleMesh coarse = geom::box(Vec3(1, 1, 1), 3); // keeps its ids through refinement
  int corners = 0;
  for (std::int32_t v = 0; v < coarse.num_vertices(); ++v)
    if (coarse.positions[v].cwiseAbs() == Vec3(0.5, 0.5, 0.5)) {
      EXPECT_EQ(sharp.positions[v], coarse.positions[v]) << "corner " << v;
      ++corners;
    }
  EXPECT_EQ(corners, 8);

  std::vector<char> none;
  const TriangleMesh rounded = build_mesh(source_of(box + "}"), 1, nullptr, &none);
  EXPECT_TRUE(none.empty());
  EXPECT_GT(off_the_unit_box(rounded), 0.05);
}

TEST(MeshSource, CreasesCrossFromTheSerialToTheDistributedRounds) {
  // 4,800 triangles: rank 0 refines twice (76,800 would pass the distributed threshold), the
  // third round is left to the parts, with the creases of the twice-refined surface.
  const MeshSource source =
      source_of("{generator: box, cells_per_edge: 20, subdivision_levels: 3, crease_angle: 60}");
  const SurfacePlan plan = plan_surface(source);
  ASSERT_EQ(plan.refinement.size(), 1u);
  EXPECT_EQ(std::count(plan.creases.begin(), plan.creases.end(), 1), 12 * 20 * 4);
  std::vector<char> creases;
  const TriangleMesh fine = build_mesh(source, 1, nullptr, &creases);
  EXPECT_EQ(std::count(creases.begin(), creases.end(), 1), 12 * 20 * 8);
  EXPECT_LT(off_the_unit_box(fine), 1e-15);
}

TEST(MeshSource, ACreaseAngleOutOfRangeNamesItsKey) {
  try {
    source_of("{generator: box, crease_angle: 200}");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("mesh.crease_angle"), std::string::npos)
        << error.what();
  }
}

} // namespace
} // namespace texsim::geom
