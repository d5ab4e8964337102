#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_validation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace texsim::geom {
namespace {

/// A unit square (triangles 0, 1) plus defects: triangle 2 repeats a vertex, triangle 3 is flat
/// (vertex 5 lies on the line through 0 and 1), triangle 4 repeats triangle 0 reversed, vertex 4
/// is used by nothing.
TriangleMesh square_with_defects() {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}, {2, 0, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 0, 1}, {0, 1, 5}, {2, 1, 0}};
  return mesh;
}

std::string message_of(TriangleMesh mesh, const MeshRepairOptions& options = {}) {
  try {
    repair(mesh, options, "shape.off");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no InputError";
}

TEST(MeshValidation, GeneratedSurfacesAreClean) {
  for (const auto& mesh : {icosphere(2), torus(3, 1, 16, 8), box(Vec3(1, 2, 3), 3)}) {
    const auto report = validate(mesh);
    EXPECT_TRUE(report.clean());
    EXPECT_EQ(report.boundary_edges, 0u);
  }
}

TEST(MeshValidation, ReportsEachDefectWithItsFirstElement) {
  const auto report = validate(square_with_defects());
  EXPECT_EQ(report.degenerate_triangles.count, 2u);
  EXPECT_EQ(report.degenerate_triangles.first, "triangle 2 (0, 0, 1) repeats a vertex");
  EXPECT_EQ(report.duplicate_triangles.count, 1u);
  EXPECT_EQ(report.duplicate_triangles.first, "triangle 4 (2, 1, 0) repeats triangle 0");
  EXPECT_EQ(report.unreferenced_vertices.count, 1u);
  EXPECT_EQ(report.unreferenced_vertices.first, "vertex 4");
  EXPECT_EQ(report.non_manifold_edges.count, 2u); // 0-1 (4 triangles) and 0-2 (3 triangles)
  EXPECT_EQ(report.non_manifold_edges.first, "vertices 0-1 shared by 4 triangles");
  EXPECT_FALSE(report.non_finite_vertices);
  EXPECT_FALSE(report.out_of_range_indices);
  EXPECT_FALSE(report.clean());
}

TEST(MeshValidation, RepairDropsDegenerateDuplicateAndUnreferenced) {
  auto mesh = square_with_defects();
  const auto report = repair(mesh, {}, "square.obj");
  EXPECT_EQ(report.merged_vertices, 0u);
  EXPECT_EQ(report.dropped_degenerate_triangles, 2u);
  EXPECT_EQ(report.dropped_duplicate_triangles, 1u);
  EXPECT_EQ(report.dropped_unreferenced_vertices, 2u); // 4 never used, 5 only by a flat triangle
  EXPECT_EQ(report.summary(), "dropped degenerate triangles: 2, dropped duplicate triangles: 1, "
                              "dropped unreferenced vertices: 2");
  ASSERT_EQ(mesh.num_vertices(), 4);
  EXPECT_EQ(mesh.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(mesh.positions[3], Vec3(0, 1, 0));
  EXPECT_TRUE(validate(mesh).clean());
}

TEST(MeshValidation, RepairRenumbersAroundUnreferencedVerticesInOrder) {
  TriangleMesh mesh;
  mesh.positions = {{9, 9, 9}, {0, 0, 0}, {8, 8, 8}, {1, 0, 0}, {0, 1, 0}, {7, 7, 7}};
  mesh.triangles = {{1, 3, 4}};
  const auto report = repair(mesh, {}, "t.off");
  EXPECT_EQ(report.dropped_unreferenced_vertices, 3u);
  EXPECT_EQ(mesh.triangles, (std::vector<Triangle>{{0, 1, 2}}));
  EXPECT_EQ(mesh.positions, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));

  MeshRepairOptions keep;
  keep.drop_unreferenced_vertices = false;
  auto kept = square_with_defects();
  repair(kept, keep, "t.off");
  EXPECT_EQ(kept.num_vertices(), 6);
  EXPECT_EQ(validate(kept).unreferenced_vertices.count, 2u);
}

TEST(MeshValidation, RepairMergesExactlyCoincidentVertices) {
  TriangleMesh soup; // a square stored as two separate triangles, as STL does
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  soup.triangles = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_EQ(validate(soup).boundary_edges, 6u);
  const auto report = repair(soup, {}, "soup.stl");
  EXPECT_EQ(report.merged_vertices, 2u);
  EXPECT_EQ(report.dropped_unreferenced_vertices, 2u);
  EXPECT_EQ(soup.num_vertices(), 4);
  const auto after = validate(soup);
  EXPECT_TRUE(after.clean());
  EXPECT_EQ(after.boundary_edges, 4u);
}

TEST(MeshValidation, DetectsInconsistentOrientation) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 2}};
  const auto report = validate(mesh);
  EXPECT_EQ(report.inconsistent_orientation.count, 1u);
  EXPECT_EQ(report.inconsistent_orientation.first, "edge 0-2 of triangles 0 and 1");
}

TEST(MeshValidation, UnrepairableDefectsThrowNamingFileCountAndFirstElement) {
  auto nan_mesh = icosphere(1);
  nan_mesh.positions[7].y() = std::numeric_limits<double>::quiet_NaN();
  nan_mesh.positions[9].z() = std::numeric_limits<double>::infinity();
  const auto nan_message = message_of(nan_mesh);
  EXPECT_NE(nan_message.find("shape.off: 2 vertices with a non-finite coordinate (first: vertex 7"),
            std::string::npos)
      << nan_message;

  TriangleMesh fin;
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_EQ(message_of(fin), "shape.off: 1 non-manifold edges (first: vertices 0-1 shared by 3 "
                             "triangles); texsim needs a manifold surface");
  MeshRepairOptions lenient;
  lenient.require_manifold_edges = false;
  EXPECT_EQ(message_of(fin, lenient), "no InputError");

  auto out_of_range = icosphere(0);
  out_of_range.triangles[3][1] = 12;
  EXPECT_NE(
      message_of(out_of_range).find("shape.off: 1 triangles with a vertex index out of range"),
      std::string::npos);

  TriangleMesh all_degenerate;
  all_degenerate.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  all_degenerate.triangles = {{0, 1, 2}};
  EXPECT_NE(message_of(all_degenerate).find("shape.off: no usable triangles"), std::string::npos);
  EXPECT_NE(message_of(TriangleMesh{}).find("shape.off: no triangles"), std::string::npos);
}

} // namespace
} // namespace texsim::geom
