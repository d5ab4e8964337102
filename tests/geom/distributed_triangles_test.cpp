#include "geom/distributed_triangles.hpp"

#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/random_surface_points.hpp"
#include "par/record_exchange.hpp"
#include "support/gather_by_id.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace texsim::geom {
namespace {

bool same_bits(const Vec3& a, const Vec3& b) {
  return std::memcmp(a.data(), b.data(), 24) == 0;
}

Vec3 corner(const TriangleRecord& r, int c) {
  return {r.corners[3 * c], r.corners[3 * c + 1], r.corners[3 * c + 2]};
}

/// A noisy sphere with a fin: one more triangle on an existing edge, which makes that edge
/// non-manifold, as raw scans have them.
TriangleMesh sphere_with_fin() {
  TriangleMesh mesh = noisy(icosphere(3), 0.01, 4);
  const Triangle& t = mesh.triangles[0];
  const Vec3 tip = 1.5 * (mesh.positions[t[0]] + mesh.positions[t[1]]) / 2.0;
  mesh.positions.push_back(tip);
  mesh.triangles.push_back({t[1], t[0], mesh.num_vertices() - 1});
  return mesh;
}

/// The shares cover the mesh once, hold its data bit for bit, and are the same whether rank 0
/// splits the mesh or every rank takes its share of its own copy; the totals are the whole
/// mesh's bits.
void expect_shares_of(const TriangleMesh& mesh) {
  const par::Comm comm = par::world();
  const auto from_root =
      DistributedTriangles::from_root(comm, comm.is_root() ? mesh : TriangleMesh{});
  const auto replicated = DistributedTriangles::from_replicated(comm, mesh);
  for (const DistributedTriangles* split : {&from_root, &replicated}) {
    EXPECT_EQ(split->global_count(), mesh.num_triangles());
    const double area = total_area(mesh), split_area = split->total_area();
    EXPECT_EQ(std::memcmp(&area, &split_area, sizeof area), 0);
    const Box3 box = Box3::around(mesh.positions);
    EXPECT_TRUE(same_bits(box.lo, split->bounds().lo) && same_bits(box.hi, split->bounds().hi));
    std::vector<std::int64_t> ids;
    for (std::size_t k = 0; k < split->owned_count(); ++k) {
      const TriangleRecord r = split->owned_record(k);
      ids.push_back(r.id);
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(r.vertex[c], mesh.triangles[std::size_t(r.id)][c]);
        ASSERT_TRUE(same_bits(corner(r, c), mesh.positions[std::size_t(r.vertex[c])]));
      }
    }
    ASSERT_TRUE(std::is_sorted(ids.begin(), ids.end()));
    // No rank holds the whole mesh (a sphere of 1280 triangles over 2 or 3 ranks).
    if (comm.size > 1) {
      EXPECT_LT(std::int64_t(ids.size()), mesh.num_triangles());
    }
    auto all = par::allgather_records(comm, ids);
    std::sort(all.begin(), all.end());
    ASSERT_EQ(std::int64_t(all.size()), mesh.num_triangles());
    for (std::size_t t = 0; t < all.size(); ++t)
      ASSERT_EQ(all[t], std::int64_t(t)) << "every triangle owned exactly once";
  }
  EXPECT_EQ(from_root.owned_surface().triangle_ids, replicated.owned_surface().triangle_ids);
}

TEST(DistributedTriangles, SharesCoverTheMeshOnce) {
  expect_shares_of(sphere_with_fin());
}

// random_points gives random_surface_points' bits on the whole mesh, whoever asks for which ids.
TEST(DistributedTriangles, RandomPointsAreTheWholeMeshsPoints) {
  const par::Comm comm = par::world();
  const TriangleMesh mesh = sphere_with_fin();
  const std::int64_t count = 5000;
  const auto expected = random_surface_points(mesh, 0, count, 9);
  for (const auto& split :
       {DistributedTriangles::from_root(comm, comm.is_root() ? mesh : TriangleMesh{}),
        DistributedTriangles::from_replicated(comm, mesh)}) {
    const std::int64_t first = count * comm.rank / comm.size;
    const std::int64_t last = count * (comm.rank + 1) / comm.size;
    const auto placed = split.random_points(comm, first, last - first, 9);
    std::vector<double> values;
    for (const auto& p : placed.points)
      values.insert(values.end(),
                    {p.position.x(), p.position.y(), p.position.z(), double(p.triangle)});
    const auto all = test::gather_by_id(comm, placed.ids, values, 4);
    ASSERT_EQ(all.size(), std::size_t(4 * count));
    for (std::int64_t id = 0; id < count; ++id) {
      const Vec3 position(all[4 * id], all[4 * id + 1], all[4 * id + 2]);
      ASSERT_TRUE(same_bits(position, expected[std::size_t(id)].position)) << "point " << id;
      ASSERT_EQ(std::int32_t(all[4 * id + 3]), expected[std::size_t(id)].triangle)
          << "point " << id;
    }
  }
}

/// Every triangle with a point within `reach` of a position is in the window (points checked: a
/// 10 x 10 barycentric grid of each triangle), and the window is numbered in the whole mesh's
/// order with its vertices.
void expect_window_of(const TriangleMesh& mesh, double reach) {
  const par::Comm comm = par::world();
  const auto split = DistributedTriangles::from_root(comm, comm.is_root() ? mesh : TriangleMesh{});
  // This rank's positions: the centroids of every seventh triangle of its share (a compact
  // region, like the points a rank relaxes).
  std::vector<Vec3> positions;
  for (std::size_t k = 0; k < split.owned_count(); k += 7) {
    const TriangleRecord r = split.owned_record(k);
    positions.push_back((corner(r, 0) + corner(r, 1) + corner(r, 2)) / 3.0);
  }
  const LocalSurface window = split.window(comm, positions, reach);
  ASSERT_TRUE(std::is_sorted(window.triangle_ids.begin(), window.triangle_ids.end()));
  ASSERT_TRUE(std::is_sorted(window.vertex_ids.begin(), window.vertex_ids.end()));
  for (std::size_t t = 0; t < window.triangle_ids.size(); ++t)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(window.vertex_ids[std::size_t(window.mesh.triangles[t][c])],
                mesh.triangles[std::size_t(window.triangle_ids[t])][c]);
  int missing = 0;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    if (window.local_triangle(t) >= 0)
      continue;
    const auto& tri = mesh.triangles[std::size_t(t)];
    // Far triangles (every point farther than reach) need no grid.
    const Vec3 centroid =
        (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
    bool near = false;
    for (const Vec3& p : positions)
      near = near || (centroid - p).norm() < reach + split.longest_edge();
    if (!near)
      continue;
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; i + j <= 10; ++j) {
        const Vec3 q = mesh.positions[tri[0]] +
                       (i / 10.0) * (mesh.positions[tri[1]] - mesh.positions[tri[0]]) +
                       (j / 10.0) * (mesh.positions[tri[2]] - mesh.positions[tri[0]]);
        for (const Vec3& p : positions)
          missing += (q - p).norm() < reach;
      }
  }
  EXPECT_EQ(missing, 0);
  // Nor does it hold far triangles: a sample of each lies in a box of points closer than a
  // cell's diagonal to one another (cells and growth both reach + h, h at most the longest edge).
  const double grown = reach + split.longest_edge();
  const double bound = (1.0 + std::sqrt(3.0)) * grown + 2.0 * split.longest_edge();
  int far = 0;
  for (const auto& tri : window.mesh.triangles) {
    const Vec3 centroid = (window.mesh.positions[tri[0]] + window.mesh.positions[tri[1]] +
                           window.mesh.positions[tri[2]]) /
                          3.0;
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec3& p : positions)
      nearest = std::min(nearest, (centroid - p).norm());
    far += nearest > bound;
  }
  EXPECT_EQ(far, 0);
  // A window is not the whole mesh when the reach is small.
  if (comm.size > 1) {
    EXPECT_LT(std::int64_t(window.triangle_ids.size()), mesh.num_triangles());
  }
}

TEST(DistributedTriangles, WindowHoldsEveryTriangleWithinReach) {
  expect_window_of(sphere_with_fin(), 0.05);
}

TEST(DistributedTrianglesOnRealData, WindowOnARawScan) {
  const auto path = test::real_data("scans/skull_ct_mc.ply");
  if (path.empty())
    GTEST_SKIP() << test::missing_data_message("scans/skull_ct_mc.ply");
  const TriangleMesh scan = read_mesh(path);
  expect_window_of(
      scan, 0.02 * (Box3::around(scan.positions).hi - Box3::around(scan.positions).lo).norm());
}

} // namespace
} // namespace texsim::geom
