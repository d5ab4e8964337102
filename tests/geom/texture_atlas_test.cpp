#include "geom/texture_atlas.hpp"

#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "img/image_io.hpp"
#include "support/test_data.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace texsim::geom {
namespace {

using Vec2 = Eigen::Vector2d;

/// The icosphere without the triangles below z = `cut`: a cap with one boundary loop.
TriangleMesh open_sphere(int level, double cut = -0.3) {
  const TriangleMesh sphere = icosphere(level);
  TriangleMesh open;
  std::vector<std::int32_t> new_id(sphere.positions.size(), -1);
  for (auto tri : sphere.triangles) {
    const double z =
        (sphere.positions[tri[0]] + sphere.positions[tri[1]] + sphere.positions[tri[2]]).z() / 3;
    if (z <= cut) {
      continue;
    }
    for (auto& v : tri) {
      if (new_id[v] < 0) {
        new_id[v] = open.num_vertices();
        open.positions.push_back(sphere.positions[v]);
      }
      v = new_id[v];
    }
    open.triangles.push_back(tri);
  }
  return open;
}

double signed_area(const std::array<Vec2, 3>& p) {
  return 0.5 * ((p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x());
}

/// The triangles' corners in texel units (v up).
std::array<Vec2, 3> in_texels(const TextureAtlas& atlas, std::int32_t t) {
  std::array<Vec2, 3> p;
  for (int i = 0; i < 3; ++i) {
    p[i] = atlas.corner_uv[t][i] * atlas.resolution;
  }
  return p;
}

/// Whether a separating axis (an edge normal of either triangle, or x or y) leaves a gap wider
/// than `gap` (in max-norm, for the axes of the square) between the triangles. gap < 0 allows that
/// much overlap (touching edges of neighbours).
bool separated(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b, double gap) {
  std::vector<Vec2> axes{Vec2::UnitX(), Vec2::UnitY()};
  for (const auto* tri : {&a, &b}) {
    for (int i = 0; i < 3; ++i) {
      const Vec2 edge = (*tri)[(i + 1) % 3] - (*tri)[i];
      axes.push_back(Vec2(-edge.y(), edge.x()).normalized());
    }
  }
  for (const Vec2& axis : axes) {
    double a_low = std::numeric_limits<double>::infinity(), a_high = -a_low;
    double b_low = a_low, b_high = -a_low;
    for (int i = 0; i < 3; ++i) {
      a_low = std::min(a_low, axis.dot(a[i]));
      a_high = std::max(a_high, axis.dot(a[i]));
      b_low = std::min(b_low, axis.dot(b[i]));
      b_high = std::max(b_high, axis.dot(b[i]));
    }
    // The max-norm ball of radius gap projects to a reach of gap * (|x| + |y|).
    const double reach = gap * (std::abs(axis.x()) + std::abs(axis.y()));
    if (b_low - a_high > reach || a_low - b_high > reach) {
      return true;
    }
  }
  return false;
}

struct AtlasCheck {
  double min_density_ratio = 0.0; ///< per triangle uv/surface area over the mean
  double max_density_ratio = 0.0;
};

/// Every uv triangle in [0, 1]^2 with positive area, every chart a disk whose uv area is
/// proportional to its surface area; optionally (small meshes) no two uv triangles overlap and
/// charts keep more than two gutters apart, by brute force over all pairs.
AtlasCheck check_atlas(const TriangleMesh& mesh, const TextureAtlas& atlas, bool brute_force) {
  AtlasCheck check;
  EXPECT_EQ(atlas.corner_uv.size(), mesh.triangles.size());
  std::vector<std::vector<std::int32_t>> charts(atlas.chart_count);
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    charts.at(atlas.chart_of_triangle[t]).push_back(t);
  }
  const double texel_area = std::pow(atlas.texels_per_unit / atlas.resolution, 2);
  double total_uv = 0.0, total_surface = 0.0;
  for (const auto& chart : charts) {
    EXPECT_TRUE(is_topological_disk(mesh, chart));
    double uv = 0.0, surface = 0.0;
    for (const auto t : chart) {
      const auto& tri = mesh.triangles[t];
      const double area = signed_area(atlas.corner_uv[t]);
      EXPECT_GT(area, 0.0) << "triangle " << t;
      for (const Vec2& p : atlas.corner_uv[t]) {
        EXPECT_TRUE(p.x() >= 0 && p.x() <= 1 && p.y() >= 0 && p.y() <= 1);
      }
      uv += area;
      surface +=
          triangle_area(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]);
    }
    EXPECT_NEAR(uv / surface, texel_area, 1e-9 * texel_area);
    total_uv += uv;
    total_surface += surface;
  }
  const double mean = total_uv / total_surface;
  check.min_density_ratio = std::numeric_limits<double>::infinity();
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& tri = mesh.triangles[t];
    const double ratio =
        signed_area(atlas.corner_uv[t]) /
        triangle_area(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]) /
        mean;
    check.min_density_ratio = std::min(check.min_density_ratio, ratio);
    check.max_density_ratio = std::max(check.max_density_ratio, ratio);
  }
  if (brute_force) {
    for (std::int32_t s = 0; s < mesh.num_triangles(); ++s) {
      for (std::int32_t t = s + 1; t < mesh.num_triangles(); ++t) {
        const bool same_chart = atlas.chart_of_triangle[s] == atlas.chart_of_triangle[t];
        const double gap = same_chart ? -1e-9 : 2.0 * atlas.gutter;
        EXPECT_TRUE(separated(in_texels(atlas, s), in_texels(atlas, t), gap))
            << "triangles " << s << " and " << t << (same_chart ? " overlap" : " too close");
      }
    }
  }
  return check;
}

/// A smooth colour per vertex in [0, 1]: linear in the position over the mesh's box.
std::vector<img::Rgb> vertex_colours(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (const Vec3& p : mesh.positions) {
    box.extend(p);
  }
  std::vector<img::Rgb> colours;
  for (const Vec3& p : mesh.positions) {
    const Vec3 c = (p - box.min()) / box.sizes().maxCoeff();
    colours.push_back(
        {static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z())});
  }
  return colours;
}

/// Fills the atlas from the vertex colours through the texels' weights, writes it as PNG and reads
/// it back; then at every triangle corner's uv the nearest texel and the bilinear sample both
/// give the corner vertex's colour within 2/255, and all four bilinear texels belong to the
/// corner's chart (the gutter keeps filtering inside the chart).
void check_filled_atlas(const TriangleMesh& mesh, const TextureAtlas& atlas,
                        const std::string& name) {
  const auto colours = vertex_colours(mesh);
  const auto texels = atlas_texels(mesh, atlas);
  const int n = atlas.resolution;
  img::RgbImage image(n, n, img::Rgb{0, 0, 0});
  std::vector<std::int32_t> chart_at(static_cast<std::size_t>(n) * n, -1);
  for (const AtlasTexel& texel : texels) {
    ASSERT_GE(texel.triangle, 0);
    const auto& tri = mesh.triangles[texel.triangle];
    double sum = 0.0;
    img::Rgb colour{0, 0, 0};
    for (int i = 0; i < 3; ++i) {
      EXPECT_GE(texel.weights[i], -1e-9);
      sum += texel.weights[i];
      const auto w = static_cast<float>(texel.weights[i]);
      colour.r += w * colours[tri[i]].r;
      colour.g += w * colours[tri[i]].g;
      colour.b += w * colours[tri[i]].b;
    }
    EXPECT_NEAR(sum, 1.0, 1e-9);
    image.at(texel.x, texel.y) = colour;
    chart_at[static_cast<std::size_t>(texel.y) * n + texel.x] =
        atlas.chart_of_triangle[texel.triangle];
  }
  const auto path = test::scratch_dir("texture_atlas_" + name) / "atlas.png";
  img::write_png(path, image);
  const img::RgbImage back = img::read_image(path);
  ASSERT_EQ(back.width(), n);

  const auto distance = [](const img::Rgb& a, const img::Rgb& b) {
    return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
  };
  double worst_nearest = 0.0, worst_bilinear = 0.0;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    for (int i = 0; i < 3; ++i) {
      const Vec2& uv = atlas.corner_uv[t][i];
      const img::Rgb& expected = colours[mesh.triangles[t][i]];
      // Texel (x, y) covers u in [x, x+1]/n and v in [n-1-y, n-y]/n.
      const int x = std::min(n - 1, static_cast<int>(std::floor(uv.x() * n)));
      const int y = std::min(n - 1, static_cast<int>(std::floor((1.0 - uv.y()) * n)));
      worst_nearest = std::max(worst_nearest, double(distance(back.at(x, y), expected)));
      const double fx = uv.x() * n - 0.5, fy = (1.0 - uv.y()) * n - 0.5;
      const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
      img::Rgb sample{0, 0, 0};
      for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
          const auto w =
              static_cast<float>((dx ? fx - x0 : 1 - (fx - x0)) * (dy ? fy - y0 : 1 - (fy - y0)));
          const img::Rgb& c = back.clamped(x0 + dx, y0 + dy);
          sample.r += w * c.r;
          sample.g += w * c.g;
          sample.b += w * c.b;
          EXPECT_EQ(chart_at[static_cast<std::size_t>(y0 + dy) * n + x0 + dx],
                    atlas.chart_of_triangle[t])
              << "bilinear texel of triangle " << t << " corner " << i;
        }
      }
      worst_bilinear = std::max(worst_bilinear, double(distance(sample, expected)));
    }
  }
  EXPECT_LE(worst_nearest, 2.0 / 255.0) << name;
  EXPECT_LE(worst_bilinear, 2.0 / 255.0) << name;
}

TEST(TextureAtlas, SphereChartsArePackedWithoutOverlapAndKeepTheGutter) {
  const TriangleMesh sphere = icosphere(2);
  const TextureAtlas atlas = build_texture_atlas(sphere, {128, 2, 60, 60.0});
  EXPECT_GT(atlas.chart_count, 1);
  const AtlasCheck check = check_atlas(sphere, atlas, true);
  EXPECT_GT(check.min_density_ratio, 0.5);
  EXPECT_LT(check.max_density_ratio, 2.0);
}

TEST(TextureAtlas, TorusAndOpenSurfaceArePackedWithoutOverlap) {
  for (const auto& mesh : {torus(1.0, 0.4, 24, 12), open_sphere(2)}) {
    const TextureAtlas atlas = build_texture_atlas(mesh, {128, 1, 5000, 60.0});
    const AtlasCheck check = check_atlas(mesh, atlas, true);
    EXPECT_GT(check.min_density_ratio, 0.5);
    EXPECT_LT(check.max_density_ratio, 2.0);
  }
}

TEST(TextureAtlas, ChartsLscmFlattensBadlyAreSplitAndRetried) {
  // Without limits the whole cap (down to 154 degrees from its pole) is one disk chart, which
  // LSCM cannot flatten within 4 times the mean density everywhere.
  const TriangleMesh cap = open_sphere(3, -0.9);
  ASSERT_EQ(segment_charts(cap, {100000, 180.0}).chart_count, 1);
  const TextureAtlas atlas = build_texture_atlas(cap, {256, 1, 100000, 180.0});
  EXPECT_GT(atlas.chart_count, 1);
  const AtlasCheck check = check_atlas(cap, atlas, true);
  EXPECT_GE(check.min_density_ratio, 0.25);
  EXPECT_LE(check.max_density_ratio, 4.0);
}

TEST(TextureAtlas, SameAtlasAndTexelsForAnyThreadCount) {
  const TriangleMesh ring = torus(1.0, 0.4, 48, 24);
  const AtlasSettings settings{256, 2, 200, 45.0};
  omp_set_num_threads(1);
  const TextureAtlas serial = build_texture_atlas(ring, settings);
  const auto serial_texels = atlas_texels(ring, serial);
  omp_set_num_threads(3);
  const TextureAtlas threaded = build_texture_atlas(ring, settings);
  const auto threaded_texels = atlas_texels(ring, threaded);
  omp_set_num_threads(1);
  EXPECT_EQ(threaded.chart_of_triangle, serial.chart_of_triangle);
  EXPECT_EQ(threaded.texels_per_unit, serial.texels_per_unit);
  for (std::size_t t = 0; t < ring.triangles.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(threaded.corner_uv[t][i], serial.corner_uv[t][i]);
    }
  }
  ASSERT_EQ(threaded_texels.size(), serial_texels.size());
  for (std::size_t i = 0; i < serial_texels.size(); ++i) {
    EXPECT_EQ(std::tie(threaded_texels[i].x, threaded_texels[i].y, threaded_texels[i].triangle,
                       threaded_texels[i].weights),
              std::tie(serial_texels[i].x, serial_texels[i].y, serial_texels[i].triangle,
                       serial_texels[i].weights));
  }
}

TEST(TextureAtlas, FilledAtlasShowsEachVertexColourAtItsUv) {
  check_filled_atlas(icosphere(4), build_texture_atlas(icosphere(4), {512, 2, 5000, 60.0}),
                     "sphere");
  const TriangleMesh ring = torus(1.0, 0.4, 64, 32);
  check_filled_atlas(ring, build_texture_atlas(ring, {512, 2, 5000, 60.0}), "torus");
  const TriangleMesh cap = open_sphere(4);
  check_filled_atlas(cap, build_texture_atlas(cap, {512, 1, 5000, 60.0}), "cap");
}

TEST(TextureAtlas, TexelsAreSortedUniqueAndInsideTheImage) {
  const TriangleMesh sphere = icosphere(3);
  const TextureAtlas atlas = build_texture_atlas(sphere, {256, 2, 5000, 60.0});
  const auto texels = atlas_texels(sphere, atlas);
  ASSERT_FALSE(texels.empty());
  for (std::size_t i = 0; i < texels.size(); ++i) {
    EXPECT_TRUE(texels[i].x >= 0 && texels[i].x < 256 && texels[i].y >= 0 && texels[i].y < 256);
    if (i > 0) {
      EXPECT_LT(std::tie(texels[i - 1].y, texels[i - 1].x), std::tie(texels[i].y, texels[i].x));
    }
  }
  // A texel whose centre lies inside a uv triangle shows exactly that point.
  for (const AtlasTexel& texel : texels) {
    const Vec2 centre((texel.x + 0.5) / 256.0, 1.0 - (texel.y + 0.5) / 256.0);
    Vec2 shown = Vec2::Zero();
    for (int i = 0; i < 3; ++i) {
      shown += texel.weights[i] * atlas.corner_uv[texel.triangle][i];
    }
    const bool inside =
        std::all_of(texel.weights.begin(), texel.weights.end(), [](double w) { return w > 1e-9; });
    if (inside) {
      EXPECT_NEAR((shown - centre).norm() * 256.0, 0.0, 1e-9);
    } else {
      EXPECT_LE((shown - centre).norm() * 256.0, std::sqrt(2.0) * 2 + 1e-9);
    }
  }
  // Same input, same atlas.
  const TextureAtlas again = build_texture_atlas(sphere, {256, 2, 5000, 60.0});
  EXPECT_EQ(again.chart_of_triangle, atlas.chart_of_triangle);
  for (std::size_t t = 0; t < sphere.triangles.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(again.corner_uv[t][i], atlas.corner_uv[t][i]);
    }
  }
}

TEST(TextureAtlas, RefusesSettingsAndResolutionsThatCannotWork) {
  EXPECT_THROW(build_texture_atlas(icosphere(1), {4, 1, 5000, 60.0}), Error);
  EXPECT_THROW(build_texture_atlas(icosphere(1), {64, -1, 5000, 60.0}), Error);
  // 1280 single-triangle charts with 5 x 5 texel cells cannot fit in 64 x 64 texels.
  EXPECT_THROW(build_texture_atlas(icosphere(3), {64, 2, 1, 60.0}), Error);
}

TEST(TextureAtlasOnRealData, BunnyAndFandiskAtlasesShowTheirVertexColours) {
  for (const std::string name : {"bunny00", "fandisk"}) {
    const auto path = test::real_data("meshes/" + name + ".off");
    if (path.empty()) {
      GTEST_SKIP() << test::missing_data_message("meshes/" + name + ".off");
    }
    const TriangleMesh mesh = read_mesh(path);
    const TextureAtlas atlas = build_texture_atlas(mesh, {1024, 2, 5000, 60.0});
    const AtlasCheck check = check_atlas(mesh, atlas, false);
    std::cout << name << ": " << atlas.chart_count << " charts, density from "
              << check.min_density_ratio << " to " << check.max_density_ratio << " of the mean\n";
    // Charts are split until every triangle is within 4 times its chart's density, the mean.
    EXPECT_GE(check.min_density_ratio, 0.25 - 1e-9);
    EXPECT_LE(check.max_density_ratio, 4.0 + 1e-9);
    check_filled_atlas(mesh, atlas, name);
  }
}

} // namespace
} // namespace texsim::geom
