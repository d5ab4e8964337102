#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_repair.hpp"
#include "geom/mesh_source.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/mesh_validation.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

namespace texsim::geom {
namespace {

/// Three triangles on edge 0-1 (a fin: the edge is non-manifold).
TriangleMesh fin() {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return mesh;
}

/// Two triangles touching at vertex 0 only (a bow tie: the vertex is non-manifold).
TriangleMesh bow_tie() {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
  return mesh;
}

MeshRepairOptions fix() {
  return MeshSource::fix_repair_options();
}

std::string strict_message(TriangleMesh mesh) {
  auto options = fix();
  options.strict = true;
  options.split_non_manifold = false;
  try {
    repair(mesh, options, "scan.ply");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no InputError";
}

TEST(MeshRepair, SplitsNonManifoldEdgesKeepingEveryTriangle) {
  auto mesh = fin();
  const auto report = repair(mesh, fix(), "fin.obj");
  EXPECT_EQ(report.non_manifold_edges, 1u);
  EXPECT_GT(report.split_added_vertices, 0u);
  EXPECT_EQ(mesh.num_triangles(), 3);
  const auto after = validate(mesh);
  EXPECT_TRUE(after.clean()) << report.summary();
  // The three triangles keep their positions: only vertex indices changed.
  auto original = fin();
  for (std::size_t t = 0; t < 3; ++t)
    for (int corner = 0; corner < 3; ++corner) {
      const auto& p = mesh.positions[mesh.triangles[t][corner]];
      const auto& q = original.positions[original.triangles[t][0]];
      const auto& r = original.positions[original.triangles[t][1]];
      const auto& s = original.positions[original.triangles[t][2]];
      EXPECT_TRUE(p == q || p == r || p == s) << "triangle " << t;
    }
}

TEST(MeshRepair, SplitsPinchedVerticesAndReorientsFlippedTriangles) {
  auto pinched = bow_tie();
  const auto report = repair(pinched, fix(), "bow_tie.obj");
  EXPECT_EQ(report.non_manifold_vertices, 1u);
  EXPECT_EQ(report.split_added_vertices, 1u);
  EXPECT_EQ(pinched.num_vertices(), 6);
  EXPECT_TRUE(validate(pinched).clean());

  TriangleMesh square;
  square.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  square.triangles = {{0, 1, 2}, {0, 3, 2}};
  const auto flipped = repair(square, fix(), "square.obj");
  EXPECT_EQ(flipped.inconsistent_orientation_edges, 1u);
  EXPECT_EQ(flipped.reoriented_triangles, 1u);
  EXPECT_EQ(flipped.split_added_vertices, 0u);
  EXPECT_TRUE(validate(square).clean());
}

TEST(MeshRepair, DropsComponentsBelowTheAreaFractionOfTheLargest) {
  auto mesh = icosphere(2, 1.0);
  auto speck = icosphere(1, 0.05); // area 0.0025 of the big sphere's
  const auto offset = mesh.num_vertices();
  for (const auto& p : speck.positions)
    mesh.positions.push_back(p + Vec3(3, 0, 0));
  for (auto tri : speck.triangles) {
    for (auto& v : tri)
      v += offset;
    mesh.triangles.push_back(tri);
  }
  auto kept = mesh;
  EXPECT_EQ(drop_small_components(kept, 0.001).dropped_components, 0u);
  EXPECT_EQ(kept.triangles, mesh.triangles);

  const auto report = repair(mesh, fix(), "two.off"); // fraction 0.01
  EXPECT_EQ(report.components, 2u);
  EXPECT_EQ(report.dropped_components, 1u);
  EXPECT_EQ(report.dropped_component_triangles, speck.triangles.size());
  EXPECT_EQ(report.dropped_unreferenced_vertices, speck.positions.size());
  EXPECT_EQ(mesh.triangles, icosphere(2, 1.0).triangles);
}

TEST(MeshRepair, FillsHolesOnlyWhenAsked) {
  auto open = icosphere(3, 1.0);
  open.triangles.erase(open.triangles.begin() + 5, open.triangles.begin() + 8);
  auto unfilled = open;
  repair(unfilled, fix(), "open.off");
  EXPECT_GT(MeshTopology(unfilled).boundary_edges().size(), 0u);

  auto options = fix();
  options.fill_holes = true;
  const auto report = repair(open, options, "open.off");
  EXPECT_GE(report.filled_holes, 1u);
  EXPECT_GE(report.hole_triangles, 3u);
  const MeshTopology topology(open);
  EXPECT_TRUE(topology.is_closed());
  EXPECT_EQ(topology.euler_characteristic(), 2);
  EXPECT_NEAR(total_area(open), total_area(icosphere(3, 1.0)), 1e-3);
}

TEST(MeshRepair, StrictRefusesNamingTheFileAndEveryDefect) {
  EXPECT_EQ(strict_message(fin()),
            "scan.ply: the mesh needs repair (mesh.repair: strict): 1 non-manifold edges "
            "(first: vertices 0-1 shared by 3 triangles); expected a clean manifold surface, or "
            "mesh.repair: fix");
  const auto pinched = strict_message(bow_tie());
  EXPECT_NE(pinched.find("1 non-manifold vertices (first: vertex 0)"), std::string::npos)
      << pinched;
  EXPECT_EQ(strict_message(icosphere(2)), "no InputError");
}

TEST(MeshRepair, RepairIsDeterministic) {
  auto a = fin(), b = fin();
  repair(a, fix(), "fin.obj");
  repair(b, fix(), "fin.obj");
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.positions, b.positions);
}

/// A marching-cubes surface of an MRI head (scripts/fetch-data): what a user brings.
TEST(MeshRepairOnRealData, MarchingCubesHeadBecomesAManifoldSurface) {
  const std::string name = "scans/ch2_head_mc_2mm.ply";
  const auto path = test::real_data(name);
  if (path.empty())
    GTEST_SKIP() << test::missing_data_message(name);
  const auto raw = validate(read_raw_mesh(path));
  EXPECT_EQ(raw.non_manifold_edges.count, 42u);
  EXPECT_GT(raw.non_manifold_vertices.count, 0u);
  // The repairs texsim refused this file for before `mesh.repair: fix`.
  EXPECT_THROW(read_mesh(path), InputError);

  RepairReport report;
  const auto mesh = read_mesh(path, fix(), &report);
  EXPECT_EQ(report.non_manifold_edges, 42u);
  EXPECT_GT(report.dropped_components, 100u);
  const auto after = validate(mesh);
  EXPECT_TRUE(after.clean()) << report.summary();
  EXPECT_GT(mesh.num_vertices(), 80000);
  EXPECT_GT(after.boundary_edges, 0u); // the neck stays open without fill_holes
}

} // namespace
} // namespace texsim::geom
