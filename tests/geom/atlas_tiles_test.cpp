// An atlas a tile at a time and split at its seams: the texels of AtlasTexelIndex::texels_in over
// any tiling are exactly atlas_texels(), triangle and weights included; splitting a closed
// sphere's atlas at its seams gives every vertex one uv, keeps positions and triangles, and
// duplicates exactly the vertices that sit on seams.
#include "geom/generators.hpp"
#include "geom/seam_split.hpp"
#include "geom/texture_atlas.hpp"

#include <gtest/gtest.h>

#include <set>

namespace texsim::geom {
namespace {

TextureAtlas sphere_atlas(const TriangleMesh& sphere) {
  AtlasSettings settings;
  settings.resolution = 128;
  settings.max_chart_triangles = 80;
  return build_texture_atlas(sphere, settings);
}

TEST(AtlasTexelIndex, AnyTilingGivesTheTexelsOfTheWholeAtlas) {
  const auto sphere = icosphere(3);
  const auto atlas = sphere_atlas(sphere);
  const auto whole = atlas_texels(sphere, atlas);
  const AtlasTexelIndex index(sphere, atlas);
  for (const int tile : {16, 37, 128}) {
    std::vector<AtlasTexel> tiled;
    for (int y = 0; y < 128; y += tile)
      for (int x = 0; x < 128; x += tile)
        for (const auto& t :
             index.texels_in({x, y, std::min(128, x + tile), std::min(128, y + tile)}))
          tiled.push_back(t);
    std::sort(tiled.begin(), tiled.end(), [](const AtlasTexel& a, const AtlasTexel& b) {
      return std::tie(a.y, a.x) < std::tie(b.y, b.x);
    });
    ASSERT_EQ(tiled.size(), whole.size()) << "tile " << tile;
    for (std::size_t i = 0; i < whole.size(); ++i) {
      ASSERT_EQ(tiled[i].x, whole[i].x);
      ASSERT_EQ(tiled[i].y, whole[i].y);
      ASSERT_EQ(tiled[i].triangle, whole[i].triangle);
      ASSERT_EQ(tiled[i].weights, whole[i].weights);
    }
  }
}

TEST(SeamSplit, OneUvPerVertexAndOnlySeamVerticesDuplicated) {
  const auto sphere = icosphere(3);
  const auto atlas = sphere_atlas(sphere);
  const auto split = split_at_seams(sphere, atlas.corner_uv);
  ASSERT_EQ(split.mesh.triangles.size(), sphere.triangles.size());
  ASSERT_EQ(split.uv.size(), split.mesh.positions.size());
  std::vector<std::set<std::int32_t>> charts_of_vertex(sphere.positions.size());
  for (std::size_t t = 0; t < sphere.triangles.size(); ++t)
    for (std::size_t c = 0; c < 3; ++c) {
      const auto v = split.mesh.triangles[t][c];
      EXPECT_EQ(split.uv[std::size_t(v)], atlas.corner_uv[t][c]);
      EXPECT_EQ(split.mesh.positions[std::size_t(v)],
                sphere.positions[std::size_t(sphere.triangles[t][c])]);
      EXPECT_EQ(split.original_vertex[std::size_t(v)], sphere.triangles[t][c]);
      charts_of_vertex[std::size_t(sphere.triangles[t][c])].insert(atlas.chart_of_triangle[t]);
    }
  // A vertex has one copy per chart it lies in (a chart's uv is continuous).
  std::size_t copies = 0;
  for (const auto& charts : charts_of_vertex)
    copies += charts.size();
  EXPECT_EQ(split.mesh.positions.size(), copies);
  EXPECT_GT(split.mesh.positions.size(), sphere.positions.size());
}

} // namespace
} // namespace texsim::geom
