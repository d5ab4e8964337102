// The lapped compositing of Gagnon et al. 2021 (5.1), distributed by atlas tiles: every texel
// shows the lowest-id patch whose texel there is not eroded (checked against a brute-force loop
// over patches and triangles), with the patch's uv at the texel's surface point; the gathered
// atlas is the same bytes for any rank count and any split of the patches; patches composited
// later never change a covered texel; a patch across a chart seam is drawn into both charts.
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "par/comm.hpp"
#include "pipelines/fluid_lapped/atlas_compositor.hpp"
#include "pipelines/fluid_lapped/patch_builder.hpp"
#include "pipelines/fluid_lapped/patch_distortion.hpp"
#include "pipelines/fluid_lapped/prepared_frames.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <set>

namespace texsim::pipelines::fluid_lapped {
namespace {

using geom::Vec3;
constexpr int kResolution = 64;
constexpr double kRadius = 0.2;

/// A feature map that erodes the patch rims: F grows from 0 to 1 along x.
ErosionMask ramp_erosion() {
  std::vector<float> feature(16 * 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      feature[std::size_t(y * 16 + x)] = float(x) / 15.0f;
  return ErosionMask(feature, 16, 16, 0.1);
}

std::vector<Patch> plane_patches(const FrameSurface& frame) {
  std::vector<Patch> patches;
  const Vec3 centres[] = {{0.3, 0.3, 0}, {0.55, 0.35, 0}, {0.4, 0.6, 0},
                          {0.7, 0.7, 0}, {0.2, 0.8, 0},   {0.5, 0.5, 0}};
  for (std::int64_t id = 0; id < 6; ++id) {
    const auto c = frame.tree.closest_point(centres[id]);
    auto patch = build_patch(frame, {c.point, c.triangle}, kRadius, id, 0, 11, std::uint64_t(id));
    // Distort each patch a little so weights (and erosion) vary over it.
    for (auto& p : patch.positions)
      p.x() += 0.02 * std::sin(7 * p.y() + double(id));
    update_weights(patch, kRadius);
    patches.push_back(std::move(patch));
  }
  return patches;
}

/// Patches i with i mod size == rank (or all on rank 0).
std::vector<Patch> share(const par::Comm& comm, const std::vector<Patch>& all, bool root_only) {
  std::vector<Patch> mine;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (root_only ? comm.rank == 0 : int(i) % comm.size == comm.rank)
      mine.push_back(all[i]);
  return mine;
}

/// The whole atlas on rank 0 (the other ranks ask for no rows).
std::vector<TexelSample> whole_on_root(const par::Comm& comm, const AtlasCompositor& compositor) {
  return compositor.rows(0, comm.rank == 0 ? compositor.resolution() : 0);
}

TEST(AtlasCompositor, LowestIdNonErodedPatchWinsEveryTexel) {
  const auto comm = par::world();
  const FrameSurface frame(geom::plane(Vec3(1, 1, 0), 20));
  const auto atlas = planar_atlas(frame.mesh, kResolution, 0);
  const auto erosion = ramp_erosion();
  const auto patches = plane_patches(frame);
  AtlasCompositor compositor(comm, frame, atlas, 16, erosion);
  compositor.composite(share(comm, patches, false));
  const auto image = whole_on_root(comm, compositor);
  if (comm.rank != 0)
    return;
  std::size_t covered = 0, eroded_somewhere = 0;
  for (int y = 0; y < kResolution; ++y)
    for (int x = 0; x < kResolution; ++x) {
      // Brute force: the texel's point, each patch in id order, its triangles in order.
      const Eigen::Vector2d point((x + 0.5) / kResolution, 1.0 - (y + 0.5) / kResolution);
      std::int64_t winner = kUncoveredTexel;
      Eigen::Vector2d winner_uv;
      for (const auto& patch : patches) {
        bool contained = false;
        for (const auto& t : patch.triangles) {
          const auto w = geom::barycentric_weights(
              patch.positions[std::size_t(t[0])], patch.positions[std::size_t(t[1])],
              patch.positions[std::size_t(t[2])], Vec3(point.x(), point.y(), 0));
          if (w[0] < -1e-9 || w[1] < -1e-9 || w[2] < -1e-9)
            continue;
          contained = true;
          Eigen::Vector2d uv = Eigen::Vector2d::Zero();
          double weight = 0;
          for (int c = 0; c < 3; ++c) {
            uv += w[std::size_t(c)] * patch.rest_uv[std::size_t(t[std::size_t(c)])];
            weight += w[std::size_t(c)] * patch.weights[std::size_t(t[std::size_t(c)])];
          }
          if (!erosion.eroded(uv, weight)) {
            winner = patch.id;
            winner_uv = uv;
            break;
          }
        }
        eroded_somewhere += contained && winner != patch.id;
        if (winner >= 0)
          break;
      }
      const auto& got = image[std::size_t(y * kResolution + x)];
      ASSERT_EQ(got.patch, winner) << "texel " << x << ", " << y;
      if (winner >= 0) {
        ++covered;
        EXPECT_NEAR(got.u, winner_uv.x(), 1e-5);
        EXPECT_NEAR(got.v, winner_uv.y(), 1e-5);
      }
    }
  EXPECT_GT(covered, std::size_t(kResolution * kResolution / 2));
  EXPECT_GT(eroded_somewhere, 0u) << "the test should see erosion decide some texels";
}

std::vector<char> bytes_of(const std::vector<TexelSample>& image) {
  std::vector<char> bytes(image.size() * sizeof(TexelSample));
  std::memcpy(bytes.data(), image.data(), bytes.size());
  return bytes;
}

TEST(AtlasCompositor, AnySplitOfThePatchesGivesTheSameBytesAndLaterPatchesOnlyFill) {
  const auto comm = par::world();
  const FrameSurface frame(geom::plane(Vec3(1, 1, 0), 20));
  const auto atlas = planar_atlas(frame.mesh, kResolution, 0);
  const auto erosion = ramp_erosion();
  const auto patches = plane_patches(frame);
  AtlasCompositor spread(comm, frame, atlas, 16, erosion);
  spread.composite(share(comm, patches, false));
  AtlasCompositor on_root(comm, frame, atlas, 24, erosion);
  on_root.composite(share(comm, patches, true));
  const auto a = whole_on_root(comm, spread), b = whole_on_root(comm, on_root);
  // In two calls: the first three, then the rest below them.
  AtlasCompositor layered(comm, frame, atlas, 16, erosion);
  const std::vector<Patch> first(patches.begin(), patches.begin() + 3),
      rest(patches.begin() + 3, patches.end());
  layered.composite(share(comm, first, false));
  const auto before = whole_on_root(comm, layered);
  layered.composite(share(comm, rest, true));
  const auto after = whole_on_root(comm, layered);
  if (comm.rank != 0)
    return;
  EXPECT_EQ(bytes_of(a), bytes_of(b));
  std::size_t filled = 0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    if (before[i].patch >= 0) {
      EXPECT_EQ(after[i].patch, before[i].patch);
    } else if (after[i].patch >= 0) {
      ++filled;
      EXPECT_GE(after[i].patch, 3);
    }
  }
  EXPECT_GT(filled, 0u);
}

TEST(AtlasCompositor, EachRankGetsTheRowsItAsksFor) {
  const auto comm = par::world();
  const FrameSurface frame(geom::plane(Vec3(1, 1, 0), 20));
  const auto atlas = planar_atlas(frame.mesh, kResolution, 0);
  const auto erosion = ramp_erosion();
  AtlasCompositor compositor(comm, frame, atlas, 24, erosion);
  compositor.composite(share(comm, plane_patches(frame), false));
  const auto all = compositor.rows(0, kResolution);
  // Overlapping ranges that cut tiles (24 rows) anywhere, one per rank.
  const int first = (7 * comm.rank) % kResolution, last = std::min(kResolution, first + 29);
  const auto some = compositor.rows(first, last);
  ASSERT_EQ(some.size(), std::size_t(last - first) * kResolution);
  const std::vector<TexelSample> expected(all.begin() + first * kResolution,
                                          all.begin() + last * kResolution);
  EXPECT_EQ(bytes_of(some), bytes_of(expected));
  EXPECT_GT(std::count_if(all.begin(), all.end(), [](const auto& s) { return s.patch >= 0; }), 0);
}

TEST(AtlasCompositor, APatchAcrossAChartSeamIsDrawnIntoBothCharts) {
  const auto comm = par::world();
  const FrameSurface frame(geom::icosphere(3));
  geom::AtlasSettings settings;
  settings.resolution = 256;
  settings.max_chart_triangles = 60; // many charts, many seams
  const auto atlas = geom::build_texture_atlas(frame.mesh, settings);
  const ErosionMask keep_all(std::vector<float>(4, 1.0f), 2, 2, 0.01);
  // The first patch whose vertices lie in several charts.
  Patch across;
  for (std::int32_t t = 0; t < frame.mesh.num_triangles() && across.id < 0; ++t) {
    const auto& tri = frame.mesh.triangles[std::size_t(t)];
    const Vec3 centre =
        (frame.mesh.positions[std::size_t(tri[0])] + frame.mesh.positions[std::size_t(tri[1])] +
         frame.mesh.positions[std::size_t(tri[2])]) /
        3.0;
    auto patch = build_patch(frame, {centre, t}, 0.3, t, 0, 3, std::uint64_t(t));
    std::set<std::int32_t> charts;
    for (const auto s : patch.surface_triangle)
      charts.insert(atlas.chart_of_triangle[std::size_t(s)]);
    if (charts.size() >= 2) {
      for (auto& w : patch.weights)
        w = 1.0;
      across = std::move(patch);
    }
  }
  ASSERT_GE(across.id, 0);
  AtlasCompositor compositor(comm, frame, atlas, 64, keep_all);
  compositor.composite(comm.rank == 0 ? std::vector<Patch>{across} : std::vector<Patch>{});
  const auto image = whole_on_root(comm, compositor);
  if (comm.rank != 0)
    return;
  const geom::AtlasTexelIndex index(frame.mesh, atlas);
  std::set<std::int32_t> charts_drawn;
  for (const auto& texel : index.texels_in({0, 0, 256, 256}))
    if (image[std::size_t(texel.y * 256 + texel.x)].patch == across.id)
      charts_drawn.insert(atlas.chart_of_triangle[std::size_t(texel.triangle)]);
  EXPECT_GE(charts_drawn.size(), 2u);
}

} // namespace
} // namespace texsim::pipelines::fluid_lapped
