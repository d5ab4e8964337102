// AtlasCompositor beyond the plain composite: gutter texels (sampling their chart's nearest point,
// up to 1.21 x gutter texels away along a slanted border) against a brute-force loop in 3D; the
// queries (coverage, winning_patches, first_uncovered, mark_unreachable) against the gathered
// atlas; covered_texels, which patch creation uses instead of compositing, against composite() of
// the lone patch on every used texel; the same bytes as a one-rank compositor; on a sphere with
// LSCM charts, every texel's patch uv within a texel of the patch's uv at the texel's surface
// point.
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "par/comm.hpp"
#include "pipelines/fluid_lapped/atlas_compositor.hpp"
#include "pipelines/fluid_lapped/frame_surface.hpp"
#include "pipelines/fluid_lapped/patch_builder.hpp"
#include "pipelines/fluid_lapped/patch_distortion.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>

namespace texsim::pipelines::fluid_lapped {
namespace {

using Eigen::Vector2d;
using geom::Vec3;
constexpr int kResolution = 64;
constexpr double kRadius = 0.2;

/// The unit square z = 0 as one chart: scaled by 1/2 and turned by 22.5 degrees about the atlas
/// centre, so its borders are slanted and gutter texels sample points up to (cos + sin) cos
/// 22.5 = 1.21 x gutter texels away in max-norm.
geom::TextureAtlas slanted_square_atlas(const geom::TriangleMesh& mesh, int gutter) {
  const double angle = std::numbers::pi / 8, scale = 0.5;
  const Eigen::Matrix2d turn =
      scale * Eigen::Rotation2Dd(angle).toRotationMatrix(); // uv about (0.5, 0.5)
  geom::TextureAtlas atlas;
  atlas.resolution = kResolution;
  atlas.gutter = gutter;
  atlas.chart_count = 1;
  atlas.texels_per_unit = kResolution * scale;
  atlas.chart_of_triangle.assign(mesh.triangles.size(), 0);
  for (const auto& t : mesh.triangles) {
    std::array<Vector2d, 3> uv;
    for (int c = 0; c < 3; ++c) {
      const auto& p = mesh.positions[std::size_t(t[std::size_t(c)])];
      uv[std::size_t(c)] = Vector2d(0.5, 0.5) + turn * Vector2d(p.x() - 0.5, p.y() - 0.5);
    }
    atlas.corner_uv.push_back(uv);
  }
  return atlas;
}

/// Image coordinates (x right, y down, in texels) of a point of the square in slanted_square_atlas.
Vector2d slanted_image(const Vec3& p) {
  const Vector2d uv = Vector2d(0.5, 0.5) + 0.5 * (Eigen::Rotation2Dd(std::numbers::pi / 8) *
                                                  Vector2d(p.x() - 0.5, p.y() - 0.5));
  return {uv.x() * kResolution, (1.0 - uv.y()) * kResolution};
}

/// F grows from 0 to 1 along x: erodes the patch rims unevenly.
ErosionMask ramp_erosion() {
  std::vector<float> feature(16 * 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      feature[std::size_t(y * 16 + x)] = float(x) / 15.0f;
  return ErosionMask(feature, 16, 16, 0.1);
}

/// F = 1 everywhere: a patch with w = 1 keeps every texel.
ErosionMask keep_all() {
  return ErosionMask(std::vector<float>(4, 1.0f), 2, 2, 0.01);
}

/// Patches at `centres` (ids in order), each bent a little so weights and erosion vary.
std::vector<Patch> patches_at(const FrameSurface& frame, const std::vector<Vec3>& centres,
                              double radius, bool bend) {
  std::vector<Patch> patches;
  for (std::size_t id = 0; id < centres.size(); ++id) {
    const auto c = frame.tree.closest_point(centres[id]);
    auto patch = build_patch(frame, {c.point, c.triangle}, radius, std::int64_t(id), 0, 5,
                             std::uint64_t(id));
    if (bend) {
      for (auto& p : patch.positions)
        p.x() += 0.02 * std::sin(7 * p.y() + double(id));
      update_weights(patch, radius);
    } else {
      patch.weights.assign(patch.weights.size(), 1.0);
    }
    patches.push_back(std::move(patch));
  }
  return patches;
}

/// Patches at the square's corners, borders and middle: they reach its gutters.
std::vector<Patch> square_patches(const FrameSurface& frame) {
  return patches_at(frame,
                    {{0.05, 0.05, 0},
                     {0.5, 0.03, 0},
                     {0.97, 0.1, 0},
                     {0.95, 0.6, 0},
                     {0.9, 0.95, 0},
                     {0.4, 0.97, 0},
                     {0.03, 0.6, 0},
                     {0.5, 0.5, 0},
                     {0.3, 0.3, 0}},
                    kRadius, true);
}

/// `patch` turned a little about an axis through the sphere's centre and projected back onto
/// the frame: its vertices no longer lie on frame vertices, as after advection.
Patch slid_on_sphere(const FrameSurface& frame, Patch patch) {
  const Eigen::AngleAxisd turn(0.03, Vec3(1, 2, 3).normalized());
  for (std::size_t v = 0; v < patch.positions.size(); ++v) {
    const auto c = frame.tree.closest_point(turn * patch.positions[v]);
    patch.positions[v] = c.point;
    patch.surface_triangle[v] = c.triangle;
  }
  return patch;
}

/// Patch i on rank i mod size.
std::vector<Patch> share(const par::Comm& comm, const std::vector<Patch>& all) {
  std::vector<Patch> mine;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (int(i) % comm.size == comm.rank)
      mine.push_back(all[i]);
  return mine;
}

std::vector<char> bytes_of(const auto& values) {
  std::vector<char> bytes(values.size() * sizeof(values[0]));
  if (!bytes.empty())
    std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

/// Whether every rank holds the same bytes.
bool same_on_every_rank(const par::Comm& comm, const std::vector<char>& bytes) {
  std::uint64_t hash = 1469598103934665603ull; // FNV-1a
  for (const char b : bytes)
    hash = (hash ^ std::uint8_t(b)) * 1099511628211ull;
  std::uint64_t low = hash, high = hash;
  MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_UINT64_T, MPI_MIN, comm.raw);
  MPI_Allreduce(MPI_IN_PLACE, &high, 1, MPI_UINT64_T, MPI_MAX, comm.raw);
  return low == high;
}

/// Every used texel with the surface point it shows (those of a compositor with no patches).
std::vector<UncoveredTexel> used_texels(const par::Comm& comm, const FrameSurface& frame,
                                        const geom::TextureAtlas& atlas,
                                        const ErosionMask& erosion) {
  const AtlasCompositor empty(comm, frame, atlas, 32, erosion);
  return empty.first_uncovered(std::numeric_limits<std::size_t>::max());
}

TEST(AtlasCompositorGutters, EveryTexelShowsTheLowestIdNonErodedPatchAtItsSurfacePoint) {
  const auto comm = par::world();
  const FrameSurface frame(geom::plane(Vec3(1, 1, 0), 20));
  const int gutter = 8;
  const auto atlas = slanted_square_atlas(frame.mesh, gutter);
  const auto erosion = ramp_erosion();
  const auto patches = square_patches(frame);
  AtlasCompositor compositor(comm, frame, atlas, 16, erosion);
  compositor.composite(share(comm, patches));
  const auto image = compositor.rows(0, compositor.resolution());
  const auto texels = used_texels(comm, frame, atlas, erosion);
  if (comm.rank != 0)
    return;
  std::size_t far_gutter_texels = 0, covered = 0;
  for (const auto& texel : texels) {
    const Vector2d centre(texel.x + 0.5, texel.y + 0.5);
    const Vector2d shown = slanted_image(texel.point.position);
    far_gutter_texels += (shown - centre).lpNorm<Eigen::Infinity>() > gutter + 1;
    // Brute force: patches in id order, their triangles in order, in 3D.
    std::int64_t winner = kUncoveredTexel;
    Vector2d winner_uv;
    for (const auto& patch : patches) {
      for (const auto& t : patch.triangles) {
        const auto w = geom::barycentric_weights(
            patch.positions[std::size_t(t[0])], patch.positions[std::size_t(t[1])],
            patch.positions[std::size_t(t[2])], texel.point.position);
        if (w[0] < -1e-9 || w[1] < -1e-9 || w[2] < -1e-9)
          continue;
        Vector2d uv = Vector2d::Zero();
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
      if (winner >= 0)
        break;
    }
    const auto& got = image[std::size_t(texel.y * kResolution + texel.x)];
    ASSERT_EQ(got.patch, winner) << "texel " << texel.x << ", " << texel.y << " shows "
                                 << (shown - centre).transpose() << " from its centre";
    if (winner >= 0) {
      ++covered;
      EXPECT_NEAR(got.u, winner_uv.x(), 1e-5);
      EXPECT_NEAR(got.v, winner_uv.y(), 1e-5);
    }
  }
  EXPECT_GT(far_gutter_texels, 0u) << "no gutter texel samples beyond gutter + 1 texels";
  EXPECT_GT(covered, texels.size() / 3);
}

TEST(AtlasCompositorQueries, AgreeWithTheGatheredAtlas) {
  const auto comm = par::world();
  const FrameSurface frame(geom::plane(Vec3(1, 1, 0), 20));
  const auto atlas = slanted_square_atlas(frame.mesh, 2);
  const auto erosion = ramp_erosion();
  const auto patches = square_patches(frame);
  AtlasCompositor compositor(comm, frame, atlas, 16, erosion);
  const std::vector<Patch> first(patches.begin(), patches.begin() + 3);
  compositor.composite(share(comm, first));
  auto image = compositor.rows(0, compositor.resolution());
  image.resize(std::size_t(kResolution * kResolution));
  MPI_Bcast(image.data(), int(image.size() * sizeof(TexelSample)), MPI_BYTE, 0, comm.raw);

  AtlasCoverage expected;
  std::vector<std::int64_t> ids;
  std::vector<std::array<int, 2>> uncovered;
  for (int y = 0; y < kResolution; ++y)
    for (int x = 0; x < kResolution; ++x) {
      const auto patch = image[std::size_t(y * kResolution + x)].patch;
      expected.used += patch != kUnusedTexel;
      expected.covered += patch >= 0;
      if (patch >= 0 && std::find(ids.begin(), ids.end(), patch) == ids.end())
        ids.push_back(patch);
      if (patch == kUncoveredTexel)
        uncovered.push_back({x, y});
    }
  std::sort(ids.begin(), ids.end());
  const auto coverage = compositor.coverage();
  EXPECT_EQ(coverage.used, expected.used);
  EXPECT_EQ(coverage.covered, expected.covered);
  EXPECT_EQ(coverage.unreachable, 0);
  EXPECT_EQ(compositor.winning_patches(), ids);
  ASSERT_GT(uncovered.size(), 60u);

  const auto listed = compositor.first_uncovered(40);
  ASSERT_EQ(listed.size(), 40u);
  for (std::size_t i = 0; i < listed.size(); ++i) {
    EXPECT_EQ(listed[i].x, uncovered[i][0]);
    EXPECT_EQ(listed[i].y, uncovered[i][1]);
  }
  std::vector<double> fields; // not the structs' bytes: their padding is undefined
  for (const auto& texel : listed)
    fields.insert(fields.end(),
                  {double(texel.x), double(texel.y), double(texel.chart),
                   double(texel.point.triangle), texel.point.position.x(), texel.point.position.y(),
                   texel.point.position.z(), double(texel.image[0]), double(texel.image[1])});
  EXPECT_TRUE(same_on_every_rank(comm, bytes_of(fields)));

  // Five texels given up: skipped from then on, counted apart, never composited.
  for (std::size_t i = 0; i < 5; ++i)
    compositor.mark_unreachable(uncovered[i][0], uncovered[i][1]);
  const auto after = compositor.first_uncovered(10);
  ASSERT_EQ(after.size(), 10u);
  EXPECT_EQ(after.front().x, uncovered[5][0]);
  EXPECT_EQ(after.front().y, uncovered[5][1]);
  EXPECT_EQ(compositor.coverage().unreachable, 5);
  compositor.composite(share(comm, patches));
  const auto last = compositor.rows(0, compositor.resolution());
  for (std::size_t i = 0; i < 5 && comm.rank == 0; ++i)
    EXPECT_EQ(last[std::size_t(uncovered[i][1] * kResolution + uncovered[i][0])].patch,
              kUnreachableTexel);
  EXPECT_EQ(compositor.coverage().unreachable, 5);
}

/// A sphere with LSCM charts small enough for many seams.
struct ChartedSphere {
  FrameSurface frame{geom::icosphere(3)};
  geom::TextureAtlas atlas;
  explicit ChartedSphere(int resolution) {
    geom::AtlasSettings settings;
    settings.resolution = resolution;
    settings.max_chart_triangles = 60;
    atlas = geom::build_texture_atlas(frame.mesh, settings);
  }
};

/// Centres spread over the unit sphere (a golden-angle spiral).
std::vector<Vec3> sphere_centres(int count) {
  std::vector<Vec3> centres;
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count, rho = std::sqrt(1.0 - z * z);
    const double phi = i * std::numbers::pi * (3.0 - std::sqrt(5.0));
    centres.emplace_back(rho * std::cos(phi), rho * std::sin(phi), z);
  }
  return centres;
}

TEST(AtlasCompositorQueries, CoveredTexelsAreWhatCompositingTheLonePatchGives) {
  const auto comm = par::world();
  const ChartedSphere sphere(128);
  const FrameSurface plane(geom::plane(Vec3(1, 1, 0), 20));
  const auto slanted = slanted_square_atlas(plane.mesh, 8);
  const auto erosion = ramp_erosion();
  struct Case {
    const FrameSurface& frame;
    const geom::TextureAtlas& atlas;
    std::vector<Patch> patches;
  };
  const Case cases[] = {
      {sphere.frame, sphere.atlas, patches_at(sphere.frame, sphere_centres(4), 0.4, true)},
      {plane, slanted, square_patches(plane)}};
  for (const auto& [frame, atlas, patches] : cases) {
    const auto texels = used_texels(comm, frame, atlas, erosion);
    for (const auto& patch : patches) {
      AtlasCompositor compositor(comm, frame, atlas, 16, erosion);
      compositor.composite(comm.rank == 0 ? std::vector<Patch>{patch} : std::vector<Patch>{});
      const auto image = compositor.rows(0, compositor.resolution());
      if (comm.rank != 0)
        continue;
      const UncoveredTexelIndex index(texels);
      std::vector<std::int32_t> composited;
      for (std::size_t i = 0; i < texels.size(); ++i)
        if (image[std::size_t(texels[i].y * atlas.resolution + texels[i].x)].patch == patch.id)
          composited.push_back(std::int32_t(i));
      EXPECT_EQ(compositor.covered_texels(compositor.image_of(patch), index), composited)
          << "patch " << patch.id;
      EXPECT_FALSE(composited.empty()) << "patch " << patch.id;
    }
  }
}

TEST(AtlasCompositorQueries, SameBytesAsOneRank) {
  const auto comm = par::world();
  const ChartedSphere sphere(128);
  const auto erosion = ramp_erosion();
  const auto patches = patches_at(sphere.frame, sphere_centres(24), 0.35, true);
  AtlasCompositor spread(comm, sphere.frame, sphere.atlas, 16, erosion);
  spread.composite(share(comm, patches));
  const auto image = spread.rows(0, spread.resolution());
  if (comm.rank != 0)
    return;
  const par::Comm self{MPI_COMM_SELF, 0, 1};
  AtlasCompositor alone(self, sphere.frame, sphere.atlas, 40, erosion);
  alone.composite(patches);
  const auto reference = alone.rows(0, alone.resolution());
  EXPECT_EQ(bytes_of(image), bytes_of(reference));
  EXPECT_GT(alone.coverage().covered, alone.coverage().used / 2);
}

TEST(AtlasCompositorQueries, SphereTexelUvIsThePatchUvAtTheTexelsSurfacePoint) {
  const auto comm = par::world();
  const ChartedSphere sphere(128);
  const auto erosion = keep_all();
  const double radius = 0.35;
  std::vector<Patch> patches;
  for (auto& patch : patches_at(sphere.frame, sphere_centres(24), radius, false))
    patches.push_back(slid_on_sphere(sphere.frame, std::move(patch)));
  AtlasCompositor compositor(comm, sphere.frame, sphere.atlas, 16, erosion);
  compositor.composite(share(comm, patches));
  const auto image = compositor.rows(0, compositor.resolution());
  const auto texels = used_texels(comm, sphere.frame, sphere.atlas, erosion);
  if (comm.rank != 0)
    return;
  // One texel in the patch's uv: r is 0.5 in uv.
  const double texel_uv = 0.5 / radius / sphere.atlas.texels_per_unit;
  double worst = 0;
  std::size_t compared = 0;
  for (const auto& texel : texels) {
    const auto& got = image[std::size_t(texel.y * sphere.atlas.resolution + texel.x)];
    if (got.patch < 0)
      continue;
    // The winning patch's uv at the texel's surface point: the patch triangle nearest it.
    const auto& patch = patches[std::size_t(got.patch)];
    double nearest = std::numeric_limits<double>::infinity();
    Vector2d uv = Vector2d::Zero();
    for (const auto& t : patch.triangles) {
      const Vec3 &a = patch.positions[std::size_t(t[0])], &b = patch.positions[std::size_t(t[1])],
                 &c = patch.positions[std::size_t(t[2])];
      const auto w = geom::barycentric_weights(a, b, c, texel.point.position);
      if (std::min({w[0], w[1], w[2]}) < -1e-6)
        continue;
      const double distance = (w[0] * a + w[1] * b + w[2] * c - texel.point.position).norm();
      if (distance < nearest) {
        nearest = distance;
        uv = w[0] * patch.rest_uv[std::size_t(t[0])] + w[1] * patch.rest_uv[std::size_t(t[1])] +
             w[2] * patch.rest_uv[std::size_t(t[2])];
      }
    }
    if (!std::isfinite(nearest))
      continue; // the point lies just outside the patch, which reaches it through the atlas map
    ++compared;
    worst = std::max(worst, (uv - Vector2d(got.u, got.v)).norm() / texel_uv);
  }
  EXPECT_GT(compared, texels.size() / 2);
  EXPECT_LT(worst, 1.0) << "texels";
  std::printf("worst uv error %.3f texels over %zu texels\n", worst, compared);
}

} // namespace
} // namespace texsim::pipelines::fluid_lapped
