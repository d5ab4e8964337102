// A rank's part of a retiled level (level_part.hpp) and the stencils flattened on parts: on the
// retiled Stanford bunny and on a sphere, split into eight runs of vertex ids, every patch that
// uses only complete triangles of its run's part is the patch the whole level gives, bit for bit,
// and under 1% do not; an eighth's part holds under half the level; parts narrower than a patch
// are caught by the completeness check; build_level_stencils (which flattens the escaped patches
// again on wider parts) gives the whole level's stencils byte for byte; a part fetched from the
// level's split triangles holds exactly the triangles the selection takes on the whole level;
// the 1-rings of a run are the topology's.
#include "geom/generators.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/point_halo.hpp"
#include "pipelines/surface_synthesis/level_part.hpp"
#include "pipelines/surface_synthesis/level_stencils.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"
#include "pipelines/surface_synthesis/orientation_field.hpp"
#include "pipelines/surface_synthesis/patch_flattening.hpp"
#include "pipelines/surface_synthesis/run_star.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr int kRuns = 8;

/// The patch radius of the {7x7} template at spacing d, as level_stencils asks for it.
double template_radius(double d) {
  return 3.0 * std::sqrt(2.0) * d + d;
}

par::Comm self() {
  return {MPI_COMM_SELF, 0, 1};
}

RetiledLevel retiled(const geom::TriangleMesh& surface, std::int64_t vertices) {
  MeshPyramidSettings settings;
  settings.finest_count = vertices;
  settings.levels = 1;
  return std::move(build_mesh_pyramid(self(), surface, 5, settings).front());
}

std::int64_t run_start(const RetiledLevel& level, int run) {
  return level.vertex_count() * run / kRuns;
}

TangentFrame frame_at(const RetiledLevel& level, std::span<const geom::Vec3> directions,
                      std::int64_t v) {
  const auto V = std::size_t(v);
  const geom::Vec3& n = level.normals[V];
  return {level.positions[V], directions[V], n.cross(directions[V]), n};
}

struct RunCheck {
  std::int64_t patches_beyond_part = 0; ///< patches using a triangle that is not complete
  std::int64_t largest_part = 0;        ///< triangles of the largest run's part
};

/// Flattens the patch of every vertex of the first `runs` runs on the whole level and on its run's
/// part grown by `growth` times patch_reach(); where the part's patch uses complete triangles
/// only, both must be the same bits (ids mapped back to the level's).
RunCheck flatten_by_runs(const RetiledLevel& level, std::span<const geom::Vec3> directions,
                         double growth, int runs = kRuns) {
  const geom::TriangleMesh mesh = gather_level_mesh(self(), level);
  const geom::MeshTopology topology(mesh);
  const double radius = template_radius(level.spacing);
  RunCheck check;
  FlattenedPatch whole, local;
  PatchScratch whole_scratch, local_scratch;
  for (int run = 0; run < runs; ++run) {
    const std::int64_t first = run_start(level, run), end = run_start(level, run + 1);
    const std::span<const geom::Vec3> centres(level.positions.data() + first,
                                              std::size_t(end - first));
    const LevelPart part(self(), level.triangles, centres, growth * patch_reach(radius));
    check.largest_part = std::max<std::int64_t>(check.largest_part, part.mesh().num_triangles());
    for (std::int64_t v = first; v < end; ++v) {
      const auto frame = frame_at(level, directions, v);
      flatten_patch(mesh, topology, topology.vertex_triangles().row(std::int32_t(v)), frame, radius,
                    whole, whole_scratch);
      const std::int32_t local_v = part.local_vertex(std::int32_t(v));
      EXPECT_GE(local_v, 0) << "vertex " << v << " is a centre of its part";
      if (local_v < 0)
        continue;
      flatten_patch(part.mesh(), part.topology(), part.topology().vertex_triangles().row(local_v),
                    frame, radius, local, local_scratch);
      if (!std::all_of(local.triangles.begin(), local.triangles.end(),
                       [&](std::int32_t t) { return part.complete(t); })) {
        ++check.patches_beyond_part;
        continue;
      }
      EXPECT_EQ(local.triangles.size(), whole.triangles.size()) << "vertex " << v;
      if (local.triangles.size() != whole.triangles.size())
        continue;
      for (std::size_t k = 0; k < whole.triangles.size(); ++k) {
        EXPECT_EQ(local.triangles[k], part.local_triangle(whole.triangles[k])) << "vertex " << v;
        for (int c = 0; c < 3; ++c) {
          EXPECT_EQ(part.global_vertex(local.vertices[k][std::size_t(c)]),
                    whole.vertices[k][std::size_t(c)]);
          EXPECT_EQ(std::memcmp(local.corners[k][std::size_t(c)].data(),
                                whole.corners[k][std::size_t(c)].data(), 2 * sizeof(double)),
                    0)
              << "vertex " << v;
        }
      }
    }
  }
  return check;
}

/// build_level_stencils of each run (parts, and wider parts for the patches that leave them)
/// against the stencils flattened on the whole level: the same bytes.
void expect_whole_level_stencils(const RetiledLevel& level,
                                 std::span<const geom::Vec3> directions) {
  const auto layout = NeighbourhoodTemplate::from_shape({7, 7, 2}, false);
  const auto positions = layout.current_positions(level.spacing);
  const geom::TriangleMesh mesh = gather_level_mesh(self(), level);
  const geom::MeshTopology topology(mesh);
  FlattenedPatch patch;
  PatchScratch scratch;
  std::vector<SampleWeights> expected(positions.size());
  for (int run = 0; run < kRuns; ++run) {
    const std::int64_t first = run_start(level, run), end = run_start(level, run + 1);
    const auto count = std::size_t(end - first);
    const auto stencils = build_level_stencils(
        self(), level, std::span(level.positions).subspan(std::size_t(first), count),
        std::span(level.normals).subspan(std::size_t(first), count),
        directions.subspan(std::size_t(first), count), nullptr, {}, layout, first, end - first);
    for (std::int64_t v = first; v < end; ++v) {
      flatten_patch(mesh, topology, topology.vertex_triangles().row(std::int32_t(v)),
                    frame_at(level, directions, v), template_radius(level.spacing), patch, scratch);
      sample_patch(patch, positions, expected);
      const auto found = stencils.current_of(v - first);
      ASSERT_EQ(found.size(), expected.size());
      EXPECT_EQ(std::memcmp(found.data(), expected.data(), expected.size() * sizeof(SampleWeights)),
                0)
          << "vertex " << v;
    }
  }
}

void expect_exact_parts(const RetiledLevel& level) {
  const auto directions = random_directions(level.normals, 3, 0);
  const auto check = flatten_by_runs(level, directions, 1.0);
  const auto vertices = level.vertex_count();
  EXPECT_LT(check.patches_beyond_part, vertices / 100) << "of " << vertices << " patches";
  EXPECT_LT(check.largest_part, level.triangle_count() / 2)
      << "an eighth's part holds " << check.largest_part << " of " << level.triangle_count()
      << " triangles";
  // Parts narrower than a patch leave patches that need triangles the parts lack, and the
  // completeness check sees them.
  EXPECT_GT(flatten_by_runs(level, directions, 0.2, 1).patches_beyond_part, vertices / kRuns / 10);
  expect_whole_level_stencils(level, directions);
}

TEST(LevelPart, PatchesOnASpheresRunsAreTheWholeLevelsPatches) {
  expect_exact_parts(retiled(geom::icosphere(4), 24576));
}

TEST(LevelPartOnRealData, PatchesOnTheBunnysRunsAreTheWholeLevelsPatches) {
  const auto path = test::real_data("meshes/bunny00.off");
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << test::missing_data_message("meshes/bunny00.off");
  expect_exact_parts(retiled(geom::read_mesh(path), 24576));
}

TEST(LevelPart, FetchedPartIsTheSelectionOnTheWholeLevel) {
  // Every triangle with a corner inside the boxes, and no other; complete where all three are.
  const RetiledLevel level = retiled(geom::icosphere(4), 6144);
  const geom::TriangleMesh mesh = gather_level_mesh(self(), level);
  const double radius = template_radius(level.spacing);
  for (const double reach : {patch_reach(radius), 0.2 * patch_reach(radius)}) {
    const std::int64_t first = run_start(level, 3), end = run_start(level, 4);
    const std::span<const geom::Vec3> centres(level.positions.data() + first,
                                              std::size_t(end - first));
    const LevelPart part(self(), level.triangles, centres, reach);
    const auto near =
        geom::inside_boxes(mesh.positions, geom::covering_boxes(centres, reach, reach));
    std::int32_t expected = 0;
    for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
      const auto& c = mesh.triangles[std::size_t(t)];
      const int near_corners =
          near[std::size_t(c[0])] + near[std::size_t(c[1])] + near[std::size_t(c[2])];
      const std::int32_t local = part.local_triangle(t);
      EXPECT_EQ(local >= 0, near_corners > 0) << "triangle " << t << ", reach " << reach;
      if (local < 0)
        continue;
      ++expected;
      EXPECT_EQ(part.complete(local), near_corners == 3) << "triangle " << t;
    }
    EXPECT_EQ(part.mesh().num_triangles(), expected) << "reach " << reach;
  }
}

TEST(LevelPart, RunRingsAreTheTopologysNeighbours) {
  const auto mesh = gather_level_mesh(self(), retiled(geom::icosphere(3), 600));
  const geom::MeshTopology topology(mesh);
  const std::int64_t first = 150, count = 200;
  const auto rings = run_rings(mesh, first, count);
  ASSERT_EQ(rings.rows(), count);
  for (std::int64_t i = 0; i < count; ++i) {
    const auto expected = topology.vertex_neighbors().row(std::int32_t(first + i));
    const auto found = rings.row(std::int32_t(i));
    EXPECT_TRUE(std::equal(found.begin(), found.end(), expected.begin(), expected.end()))
        << "vertex " << first + i;
  }
}

} // namespace
} // namespace texsim::pipelines::surface_synthesis
