#include "geom/chart_segmentation.hpp"

#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_reader.hpp"
#include "support/test_data.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace texsim::geom {
namespace {

/// The icosphere without the triangles below z = -0.3: a cap with one boundary loop.
TriangleMesh open_sphere(int level) {
  const TriangleMesh sphere = icosphere(level);
  TriangleMesh open;
  open.positions = sphere.positions;
  for (const auto& tri : sphere.triangles) {
    const double z =
        (sphere.positions[tri[0]] + sphere.positions[tri[1]] + sphere.positions[tri[2]]).z() / 3;
    if (z > -0.3) {
      open.triangles.push_back(tri);
    }
  }
  std::vector<std::int32_t> new_id(open.positions.size(), -1);
  TriangleMesh compact;
  for (auto tri : open.triangles) {
    for (auto& v : tri) {
      if (new_id[v] < 0) {
        new_id[v] = compact.num_vertices();
        compact.positions.push_back(open.positions[v]);
      }
      v = new_id[v];
    }
    compact.triangles.push_back(tri);
  }
  return compact;
}

std::vector<std::vector<std::int32_t>> charts_of(const ChartSegmentation& segmentation) {
  std::vector<std::vector<std::int32_t>> charts(segmentation.chart_count);
  for (std::int32_t t = 0; t < static_cast<std::int32_t>(segmentation.chart_of_triangle.size());
       ++t) {
    charts.at(segmentation.chart_of_triangle[t]).push_back(t);
  }
  return charts;
}

Vec3 normal_of(const TriangleMesh& mesh, std::int32_t t) {
  const auto& tri = mesh.triangles[t];
  return (mesh.positions[tri[1]] - mesh.positions[tri[0]])
      .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]])
      .normalized();
}

/// Every chart a disk within the size limit, chart ids in order of their smallest triangle, and
/// some triangle of each chart (its seed) within the normal deviation of all the others.
void expect_valid_segmentation(const TriangleMesh& mesh, const ChartSettings& settings,
                               bool check_normals) {
  const ChartSegmentation segmentation = segment_charts(mesh, settings);
  ASSERT_EQ(segmentation.chart_of_triangle.size(), mesh.triangles.size());
  const auto charts = charts_of(segmentation);
  const double min_cosine =
      std::cos(settings.max_normal_deviation_degrees * std::numbers::pi / 180.0) - 1e-12;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    ASSERT_FALSE(charts[c].empty()) << "chart " << c;
    EXPECT_TRUE(is_topological_disk(mesh, charts[c])) << "chart " << c;
    EXPECT_LE(static_cast<std::int32_t>(charts[c].size()), settings.max_chart_triangles);
    if (c > 0) {
      EXPECT_LT(charts[c - 1].front(), charts[c].front());
    }
    if (check_normals) {
      const bool has_centre = std::any_of(charts[c].begin(), charts[c].end(), [&](auto seed) {
        return std::all_of(charts[c].begin(), charts[c].end(), [&](auto t) {
          return normal_of(mesh, seed).dot(normal_of(mesh, t)) >= min_cosine;
        });
      });
      EXPECT_TRUE(has_centre) << "chart " << c;
    }
  }
  EXPECT_EQ(segment_charts(mesh, settings).chart_of_triangle, segmentation.chart_of_triangle);
}

TEST(ChartSegmentation, SphereChartsAreDisksWithinTheLimits) {
  expect_valid_segmentation(icosphere(3), {200, 45.0}, true);
  expect_valid_segmentation(icosphere(3), {5000, 60.0}, true);
}

TEST(ChartSegmentation, TorusChartsAreDisks) {
  expect_valid_segmentation(torus(1.0, 0.4, 32, 16), {300, 60.0}, true);
  // Without a normal limit, the disk rule alone stops the chart from closing around the handles.
  expect_valid_segmentation(torus(1.0, 0.4, 32, 16), {100000, 180.0}, false);
}

TEST(ChartSegmentation, OpenSurfaceChartsAreDisks) {
  const TriangleMesh cap = open_sphere(3);
  ASSERT_FALSE(MeshTopology(cap).is_closed());
  expect_valid_segmentation(cap, {150, 60.0}, true);
  // The whole cap is already a disk: with no limits it is one chart.
  EXPECT_EQ(segment_charts(cap, {100000, 180.0}).chart_count, 1);
}

TEST(ChartSegmentation, IsTopologicalDiskTellsDisksFromOtherSurfaces) {
  const TriangleMesh sphere = icosphere(1);
  std::vector<std::int32_t> all(sphere.triangles.size());
  for (std::size_t t = 0; t < all.size(); ++t) {
    all[t] = static_cast<std::int32_t>(t);
  }
  EXPECT_FALSE(is_topological_disk(sphere, all)); // closed
  EXPECT_TRUE(is_topological_disk(sphere, std::vector<std::int32_t>{0}));
  EXPECT_FALSE(is_topological_disk(sphere, {}));

  // A band around the torus's tube is an annulus (Euler characteristic 0).
  const TriangleMesh ring = torus(1.0, 0.4, 8, 6);
  std::vector<std::int32_t> band;
  for (std::int32_t t = 0; t < ring.num_triangles(); ++t) {
    const auto& tri = ring.triangles[t];
    if (std::all_of(tri.begin(), tri.end(), [&](auto v) { return v < 2 * 6; })) {
      band.push_back(t);
    }
  }
  ASSERT_FALSE(band.empty());
  EXPECT_FALSE(is_topological_disk(ring, band));

  // Two triangles sharing only a vertex: not manifold, not connected by an edge.
  TriangleMesh bowtie;
  bowtie.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0), Vec3(-1, -1, 0)};
  bowtie.triangles = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_FALSE(is_topological_disk(bowtie, std::vector<std::int32_t>{0, 1}));
}

TEST(ChartSegmentation, SplitChartCutsADiskIntoDisksCoveringIt) {
  const TriangleMesh cap = open_sphere(3);
  const MeshTopology topology(cap);
  std::vector<std::int32_t> all(cap.triangles.size());
  for (std::size_t t = 0; t < all.size(); ++t) {
    all[t] = static_cast<std::int32_t>(t);
  }
  const auto pieces = split_chart(cap, topology, all);
  ASSERT_GE(pieces.size(), 2u);
  std::vector<std::int32_t> covered;
  for (const auto& piece : pieces) {
    EXPECT_TRUE(is_topological_disk(cap, piece));
    EXPECT_TRUE(std::is_sorted(piece.begin(), piece.end()));
    covered.insert(covered.end(), piece.begin(), piece.end());
  }
  std::sort(covered.begin(), covered.end());
  EXPECT_EQ(covered, all);
  // Two seeds at opposite ends share the cap roughly evenly.
  EXPECT_GT(pieces[0].size(), all.size() / 5);

  const std::vector<std::int32_t> two{0, 1};
  EXPECT_EQ(split_chart(cap, topology, two).size(), 2u);
  EXPECT_THROW(split_chart(cap, topology, std::vector<std::int32_t>{3}), Error);
}

TEST(ChartSegmentation, RefusesInvalidSettings) {
  EXPECT_THROW(segment_charts(icosphere(1), {0, 60.0}), Error);
  EXPECT_THROW(segment_charts(icosphere(1), {10, 0.0}), Error);
  EXPECT_THROW(segment_charts(icosphere(1), {10, 181.0}), Error);
}

TEST(ChartSegmentationOnRealData, BunnyAndFandiskChartsAreDisks) {
  for (const char* name : {"meshes/bunny00.off", "meshes/fandisk.off"}) {
    const auto path = test::real_data(name);
    if (path.empty()) {
      GTEST_SKIP() << test::missing_data_message(name);
    }
    expect_valid_segmentation(read_mesh(path), {5000, 60.0}, false);
  }
}

} // namespace
} // namespace texsim::geom
