// Flattening and resampling mesh patches (Wei and Levoy 2001, section 3.3): template samples land
// on the vertices of a regular grid; rotated frames and off-vertex origins interpolate linear
// functions exactly; cylinder patches keep edge lengths and develop consistently; folds beyond
// 90 degrees stop growth while milder ones are unfolded isometrically; mesh boundaries leave
// samples uncovered.
#include "geom/generators.hpp"
#include "geom/mesh_topology.hpp"
#include "pipelines/surface_synthesis/patch_flattening.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <set>

namespace texsim::pipelines::surface_synthesis {
namespace {

using geom::Vec3;

constexpr double kTolerance = 1e-12;
/// Through SampleWeights, whose weights are floats: about 1e-7 of the coordinates here.
constexpr double kWeightTolerance = 1e-6;

/// Triangulates a (columns x rows)-vertex parameter grid, vertex (i, j) at id j * columns + i
/// placed by `place`, each cell split into two triangles counter-clockwise in parameter space.
geom::TriangleMesh parameter_grid(int columns, int rows,
                                  const std::function<Vec3(int, int)>& place) {
  geom::TriangleMesh mesh;
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < columns; ++i) {
      mesh.positions.push_back(place(i, j));
    }
  }
  for (int j = 0; j + 1 < rows; ++j) {
    for (int i = 0; i + 1 < columns; ++i) {
      const std::int32_t v = j * columns + i;
      mesh.triangles.push_back({v, v + 1, v + columns + 1});
      mesh.triangles.push_back({v, v + columns + 1, v + columns});
    }
  }
  return mesh;
}

/// Regular planar grid in z = 0, spacing h: right triangles of area h^2 / 2, so d = sqrt(2A) = h.
geom::TriangleMesh planar_grid(int columns, int rows, double h) {
  return parameter_grid(columns, rows, [h](int i, int j) { return Vec3(i * h, j * h, 0.0); });
}

/// The lead's template layout: sample (dx, dy) in pixel offsets at (dx * spacing, -dy * spacing),
/// dx fastest, dy from -half to half.
std::vector<Eigen::Vector2d> template_positions(int half, double spacing) {
  std::vector<Eigen::Vector2d> positions;
  for (int dy = -half; dy <= half; ++dy) {
    for (int dx = -half; dx <= half; ++dx) {
      positions.emplace_back(dx * spacing, -dy * spacing);
    }
  }
  return positions;
}

/// Radius the pipeline asks for: the template's corner plus one triangle.
double template_radius(int half, double spacing, double triangle) {
  return half * spacing * std::numbers::sqrt2 + triangle;
}

std::vector<std::int32_t> triangles_around(const geom::MeshTopology& topology, std::int32_t v) {
  const auto row = topology.vertex_triangles().row(v);
  return {row.begin(), row.end()};
}

TangentFrame frame_at(const Vec3& origin, const Vec3& s, const Vec3& n) {
  return {origin, s.normalized(), n.normalized().cross(s.normalized()), n.normalized()};
}

std::vector<SampleWeights> sample(const FlattenedPatch& patch,
                                  const std::vector<Eigen::Vector2d>& positions) {
  std::vector<SampleWeights> weights(positions.size());
  sample_patch(patch, positions, weights);
  return weights;
}

Vec3 interpolated_position(const geom::TriangleMesh& mesh, const SampleWeights& w) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    p += double(w.weights[i]) * mesh.positions[w.vertices[i]];
  }
  return p;
}

/// Distance from `origin` to a triangle lying in the plane z = 0 (brute-force reference).
double planar_distance(const geom::TriangleMesh& mesh, std::int32_t t, const Vec3& origin) {
  std::array<Eigen::Vector2d, 3> c;
  for (int i = 0; i < 3; ++i) {
    c[i] = (mesh.positions[mesh.triangles[t][i]] - origin).head<2>();
  }
  FlattenedPatch one{{t}, {mesh.triangles[t]}, {c}};
  SampleWeights inside;
  const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
  sample_patch(one, {&zero, 1}, {&inside, 1});
  if (inside.covered()) {
    return 0.0;
  }
  double distance = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d a = c[i], ab = c[(i + 1) % 3] - c[i];
    const double along = std::clamp(-a.dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    distance = std::min(distance, (a + along * ab).norm());
  }
  return distance;
}

/// Every flattened triangle's three edges against the 3D ones, relative.
double worst_edge_length_error(const geom::TriangleMesh& mesh, const FlattenedPatch& patch,
                               const std::set<std::int32_t>& skip_triangles = {}) {
  double worst = 0.0;
  for (std::size_t k = 0; k < patch.triangles.size(); ++k) {
    if (skip_triangles.contains(patch.triangles[k])) {
      continue;
    }
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      const double length3 =
          (mesh.positions[patch.vertices[k][j]] - mesh.positions[patch.vertices[k][i]]).norm();
      const double length2 = (patch.corners[k][j] - patch.corners[k][i]).norm();
      worst = std::max(worst, std::abs(length2 - length3) / length3);
    }
  }
  return worst;
}

TEST(PatchFlattening, GridTemplateSamplesHitTheGridVertices) {
  constexpr int kColumns = 21, kHalf = 3;
  constexpr double h = 0.1;
  const auto mesh = planar_grid(kColumns, kColumns, h);
  const geom::MeshTopology topology(mesh);
  const auto positions = template_positions(kHalf, h);
  PatchScratch scratch;
  FlattenedPatch patch;
  // Both grid-aligned frames: s along +x (t = +y) and s along +y (t = -x).
  for (const Vec3& s : {Vec3(1, 0, 0), Vec3(0, 1, 0)}) {
    for (const int centre : {10 * kColumns + 10, 4 * kColumns + 16}) {
      const TangentFrame frame = frame_at(mesh.positions[centre], s, Vec3(0, 0, 1));
      const double radius = template_radius(kHalf, h, h);
      flatten_patch(mesh, topology, triangles_around(topology, centre), frame, radius, patch,
                    scratch);

      // On a plane every triangle within the radius is reached, and nothing else.
      std::set<std::int32_t> expected;
      for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
        if (planar_distance(mesh, t, frame.origin) <= radius) {
          expected.insert(t);
        }
      }
      const std::set<std::int32_t> added(patch.triangles.begin(), patch.triangles.end());
      EXPECT_EQ(added, expected);
      EXPECT_EQ(added.size(), patch.triangles.size()) << "a triangle was added twice";
      EXPECT_LT(worst_edge_length_error(mesh, patch), kTolerance);

      const auto weights = sample(patch, positions);
      for (std::size_t k = 0; k < positions.size(); ++k) {
        const int dx = static_cast<int>(k % 7) - kHalf, dy = static_cast<int>(k / 7) - kHalf;
        // Flattened (dx h, -dy h) is the 3D point centre + dx h s - dy h t.
        const Vec3 target = frame.origin + dx * h * frame.s - dy * h * frame.t;
        const auto vertex = static_cast<std::int32_t>(std::lround(target.y() / h) * kColumns +
                                                      std::lround(target.x() / h));
        ASSERT_TRUE(weights[k].covered()) << "sample " << dx << ", " << dy;
        int ones = 0;
        for (int i = 0; i < 3; ++i) {
          if (std::abs(weights[k].weights[i] - 1.0) < kWeightTolerance) {
            ++ones;
            EXPECT_EQ(weights[k].vertices[i], vertex) << "sample " << dx << ", " << dy;
          } else {
            EXPECT_LT(std::abs(weights[k].weights[i]), kWeightTolerance);
          }
        }
        EXPECT_EQ(ones, 1) << "sample " << dx << ", " << dy;
      }
    }
  }
}

TEST(PatchFlattening, RotatedFramesAndOffVertexOriginsInterpolateLinearFunctionsExactly) {
  constexpr int kColumns = 25;
  constexpr double h = 0.1;
  // Vertices jittered inside the plane: irregular triangles, still a plane.
  const auto mesh = parameter_grid(kColumns, kColumns, [](int i, int j) {
    return Vec3((i + 0.15 * std::sin(1.7 * i + 2.3 * j)) * h,
                (j + 0.15 * std::cos(2.9 * i - 1.1 * j)) * h, 0.0);
  });
  for (const auto& t : mesh.triangles) {
    ASSERT_GT((mesh.positions[t[1]] - mesh.positions[t[0]])
                  .cross(mesh.positions[t[2]] - mesh.positions[t[0]])
                  .z(),
              0.0);
  }
  const geom::MeshTopology topology(mesh);
  const auto linear = [](const Vec3& p) { return 1.5 + 2.0 * p.x() - 3.0 * p.y(); };
  PatchScratch scratch;
  FlattenedPatch patch;
  for (const double angle : {0.3, 1.9, -2.4}) {
    // Origin inside the seed triangle, as when the seed is a parent face on the coarser level.
    const std::int32_t seed = 2 * (12 * (kColumns - 1) + 11) + 1;
    const auto& v = mesh.triangles[seed];
    const Vec3 origin =
        0.2 * mesh.positions[v[0]] + 0.5 * mesh.positions[v[1]] + 0.3 * mesh.positions[v[2]];
    const TangentFrame frame =
        frame_at(origin, Vec3(std::cos(angle), std::sin(angle), 0), Vec3(0, 0, 1));
    // Current level (7x7 at d) and a coarser-level template at 2d.
    for (const auto& [half, spacing] : {std::pair{3, h}, std::pair{2, 2 * h}}) {
      auto positions = template_positions(half, spacing);
      flatten_patch(mesh, topology, std::array{seed}, frame, template_radius(half, spacing, 2 * h),
                    patch, scratch);
      EXPECT_LT(worst_edge_length_error(mesh, patch), kTolerance);
      const auto weights = sample(patch, positions);
      for (std::size_t k = 0; k < positions.size(); ++k) {
        ASSERT_TRUE(weights[k].covered());
        const Vec3 target = origin + positions[k].x() * frame.s + positions[k].y() * frame.t;
        double value = 0.0;
        for (int i = 0; i < 3; ++i) {
          value += weights[k].weights[i] * linear(mesh.positions[weights[k].vertices[i]]);
        }
        EXPECT_NEAR(value, linear(target), kWeightTolerance);
        EXPECT_LT((interpolated_position(mesh, weights[k]) - target).norm(), kWeightTolerance);
      }
    }
  }
}

TEST(PatchFlattening, CylinderPatchesKeepEdgeLengthsAndCoverTheTemplate) {
  // Radius 1, 96 columns around (h ~ 0.065), rings at spacing 0.07: every grid cell is a planar
  // rectangle, so the surface develops onto the plane and unfolding is an isometry.
  constexpr int kAround = 96, kRings = 40;
  constexpr double kRing = 0.07;
  const double column = 2.0 * std::numbers::pi / kAround;
  auto mesh = parameter_grid(kAround + 1, kRings, [&](int i, int j) {
    return Vec3(std::cos(i * column), std::sin(i * column), j * kRing);
  });
  // Close the seam: column kAround is column 0 (triangles are counter-clockwise seen from outside).
  for (auto& triangle : mesh.triangles) {
    for (auto& v : triangle) {
      if (v % (kAround + 1) == kAround) {
        v -= kAround;
      }
    }
  }
  const geom::MeshTopology topology(mesh);
  ASSERT_TRUE(topology.is_manifold());
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    area += (mesh.positions[t[1]] - mesh.positions[t[0]])
                .cross(mesh.positions[t[2]] - mesh.positions[t[0]])
                .norm() /
            2.0;
  }
  const double d = std::sqrt(2.0 * area / mesh.num_triangles());
  const auto positions = template_positions(3, d);
  const double radius = template_radius(3, d, 2 * d);
  PatchScratch scratch;
  FlattenedPatch patch;

  // A single seed triangle with the frame in its plane (the coarser level's parent face): the
  // projection is exact, so every triangle keeps its edges, and a vertex met through two paths
  // lands on one place.
  const std::int32_t seed = 2 * (20 * kAround + 5);
  const auto& v = mesh.triangles[seed];
  const Vec3 a = mesh.positions[v[0]], b = mesh.positions[v[1]], c = mesh.positions[v[2]];
  for (const Vec3& s : {Vec3(b - a), Vec3(0, 0, 1).cross((b - a).cross(c - a))}) {
    const TangentFrame frame = frame_at((a + b + c) / 3.0, s, (b - a).cross(c - a));
    flatten_patch(mesh, topology, std::array{seed}, frame, radius, patch, scratch);
    EXPECT_GT(patch.triangles.size(), 100u);
    EXPECT_LT(worst_edge_length_error(mesh, patch), kTolerance);
    std::map<std::int32_t, Eigen::Vector2d> place;
    for (std::size_t k = 0; k < patch.triangles.size(); ++k) {
      for (int i = 0; i < 3; ++i) {
        const auto [it, first] = place.emplace(patch.vertices[k][i], patch.corners[k][i]);
        EXPECT_LT((it->second - patch.corners[k][i]).norm(), kTolerance * d);
      }
    }
    for (const auto& w : sample(patch, positions)) {
      EXPECT_TRUE(w.covered());
    }
  }

  // The fan around a vertex projected onto its tangent plane: the projection shortens seed edges
  // (relative 1 - cos of their tilt); unfolding adds no distortion of its own, so an edge closing
  // between two placed vertices is off by at most about their two placement errors (measured:
  // 2.0x the worst seed shortening), and errors do not grow with the distance from the seeds.
  const std::int32_t centre = 20 * (kAround + 1) + 7;
  const Vec3 normal(mesh.positions[centre].x(), mesh.positions[centre].y(), 0.0);
  const TangentFrame frame = frame_at(mesh.positions[centre], Vec3(0, 0, 1).cross(normal), normal);
  const auto seeds = triangles_around(topology, centre);
  flatten_patch(mesh, topology, seeds, frame, radius, patch, scratch);
  const std::set<std::int32_t> seed_set(seeds.begin(), seeds.end());
  ASSERT_GT(patch.triangles.size(), seeds.size());
  const auto seed_count = static_cast<std::ptrdiff_t>(seeds.size());
  const FlattenedPatch seed_patch{{patch.triangles.begin(), patch.triangles.begin() + seed_count},
                                  {patch.vertices.begin(), patch.vertices.begin() + seed_count},
                                  {patch.corners.begin(), patch.corners.begin() + seed_count}};
  ASSERT_EQ(seed_patch.triangles, seeds) << "seeds come first, in order";
  const double seed_shortening = worst_edge_length_error(mesh, seed_patch);
  EXPECT_GT(seed_shortening, 1e-4);
  EXPECT_LT(worst_edge_length_error(mesh, patch, seed_set), 3.0 * seed_shortening);
  for (const auto& w : sample(patch, positions)) {
    EXPECT_TRUE(w.covered());
  }
}

TEST(PatchFlattening, SpherePatchesHaveNoCracksWhereGrowthFrontsMeet) {
  // Positive curvature leaves a wedge between fronts growing around a region; placing each vertex
  // once closes it, so every template sample is covered (placing each triangle on its own left
  // 0.5% of the samples in such cracks on icospheres of 10k and 41k vertices).
  const auto mesh = geom::icosphere(4);
  const geom::MeshTopology topology(mesh);
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    area += (mesh.positions[t[1]] - mesh.positions[t[0]])
                .cross(mesh.positions[t[2]] - mesh.positions[t[0]])
                .norm() /
            2.0;
  }
  const double d = std::sqrt(2.0 * area / mesh.num_triangles());
  const auto positions = template_positions(3, d);
  PatchScratch scratch;
  FlattenedPatch patch;
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 n = mesh.positions[v].normalized();
    const Vec3 s = Eigen::AngleAxisd(0.37 * v, n) * n.unitOrthogonal();
    flatten_patch(mesh, topology, triangles_around(topology, v), frame_at(mesh.positions[v], s, n),
                  template_radius(3, d, d), patch, scratch);
    std::map<std::int32_t, Eigen::Vector2d> place;
    for (std::size_t k = 0; k < patch.triangles.size(); ++k) {
      for (int i = 0; i < 3; ++i) {
        const auto [it, first] = place.emplace(patch.vertices[k][i], patch.corners[k][i]);
        ASSERT_TRUE(it->second == patch.corners[k][i]) << "vertex " << it->first << " placed twice";
      }
    }
    const auto weights = sample(patch, positions);
    for (std::size_t k = 0; k < positions.size(); ++k) {
      ASSERT_TRUE(weights[k].covered()) << "vertex " << v << ", sample " << k;
    }
    EXPECT_LT((interpolated_position(mesh, weights[24]) - mesh.positions[v]).norm(),
              kWeightTolerance);
  }
}

/// A strip folded along x = 0: parameter a <= 0 is the plane z = 0, then a flap of width
/// `flap` rising at `angle` from the +x direction, then a strip going +x again at the flap's
/// height. Vertex columns at a = (i - 8) h, rows at y = (j - 8) h.
struct FoldedStrip {
  double h, flap, angle;
  Vec3 place(double a, double y) const {
    const Vec3 up(std::cos(angle), 0.0, std::sin(angle));
    if (a <= 0.0) {
      return {a, y, 0.0};
    }
    if (a <= flap) {
      return a * up + Vec3(0, y, 0);
    }
    return flap * up + Vec3(a - flap, y, 0);
  }
  geom::TriangleMesh mesh() const {
    return parameter_grid(21, 17, [this](int i, int j) { return place((i - 8) * h, (j - 8) * h); });
  }
};

TEST(PatchFlattening, FoldsBeyondNinetyDegreesStopGrowth) {
  constexpr double h = 0.1;
  const FoldedStrip strip{h, 2 * h, 150.0 * std::numbers::pi / 180.0};
  const auto mesh = strip.mesh();
  const geom::MeshTopology topology(mesh);
  const std::int32_t centre = 8 * 21 + 6; // a = -2h, y = 0
  const TangentFrame frame = frame_at(mesh.positions[centre], Vec3(1, 0, 0), Vec3(0, 0, 1));
  PatchScratch scratch;
  FlattenedPatch patch;
  flatten_patch(mesh, topology, triangles_around(topology, centre), frame, template_radius(3, h, h),
                patch, scratch);
  // Only base triangles (columns a < 0): the flap faces away, and the strip beyond it, which faces
  // +z again and lies right above the base, is reachable only through the flap.
  std::size_t base_within_radius = 0;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const int column = (t / 2) % 20;
    base_within_radius +=
        column < 8 && planar_distance(mesh, t, frame.origin) <= template_radius(3, h, h);
  }
  EXPECT_EQ(patch.triangles.size(), base_within_radius);
  for (const std::int32_t t : patch.triangles) {
    EXPECT_LT((t / 2) % 20, 8) << "triangle " << t << " is not on the base";
  }
  const auto positions = template_positions(3, h);
  const auto weights = sample(patch, positions);
  for (std::size_t k = 0; k < positions.size(); ++k) {
    // Samples up to the fold line (x = 0, i.e. 2 h right of the centre) lie on the base.
    EXPECT_EQ(weights[k].covered(), positions[k].x() <= 2 * h + kTolerance) << "sample " << k;
  }
}

TEST(PatchFlattening, FoldsBelowNinetyDegreesAreUnfoldedIsometrically) {
  constexpr double h = 0.1;
  const FoldedStrip strip{h, 2 * h, 60.0 * std::numbers::pi / 180.0};
  const auto mesh = strip.mesh();
  const geom::MeshTopology topology(mesh);
  const std::int32_t centre = 8 * 21 + 6;
  const TangentFrame frame = frame_at(mesh.positions[centre], Vec3(1, 0, 0), Vec3(0, 0, 1));
  PatchScratch scratch;
  FlattenedPatch patch;
  flatten_patch(mesh, topology, triangles_around(topology, centre), frame, template_radius(3, h, h),
                patch, scratch);
  EXPECT_LT(worst_edge_length_error(mesh, patch), kTolerance);
  const auto positions = template_positions(3, h);
  const auto weights = sample(patch, positions);
  for (std::size_t k = 0; k < positions.size(); ++k) {
    ASSERT_TRUE(weights[k].covered());
    // The strip is developable: flattened (x, y) is the point at parameter (x - 2h, y).
    const Vec3 target = strip.place(positions[k].x() - 2 * h, positions[k].y());
    EXPECT_LT((interpolated_position(mesh, weights[k]) - target).norm(), kWeightTolerance);
  }
}

TEST(PatchFlattening, ATriangleFlippedBetweenPlacedVerticesIsNotAdded) {
  // A saddle vertex: 8 triangles around the origin, ring vertices alternately at z = +-0.5, all
  // facing +z, their angles at the centre summing to 548 degrees. Grown from one of them, the fan
  // wraps past a full turn; the last triangle, whose vertices are all placed by then, comes out
  // flipped and stays out.
  geom::TriangleMesh mesh;
  mesh.positions.emplace_back(0.0, 0.0, 0.0);
  for (int k = 0; k < 8; ++k) {
    const double angle = k * std::numbers::pi / 4.0;
    mesh.positions.emplace_back(std::cos(angle), std::sin(angle), k % 2 == 0 ? 0.5 : -0.5);
  }
  for (int k = 0; k < 8; ++k) {
    mesh.triangles.push_back({0, k + 1, (k + 1) % 8 + 1});
  }
  const geom::MeshTopology topology(mesh);
  const TangentFrame frame = frame_at(Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 0, 1));
  PatchScratch scratch;
  FlattenedPatch patch;
  flatten_patch(mesh, topology, std::array{0}, frame, 10.0, patch, scratch);
  EXPECT_EQ(patch.triangles, (std::vector<std::int32_t>{0, 1, 2, 3, 4, 5, 6}));
}

TEST(PatchFlattening, SamplesBeyondAMeshBoundaryAreUncovered) {
  constexpr int kColumns = 5;
  constexpr double h = 0.1;
  const auto mesh = planar_grid(kColumns, kColumns, h);
  const geom::MeshTopology topology(mesh);
  PatchScratch scratch;
  FlattenedPatch patch;
  for (const std::int32_t centre : {0, 1 * kColumns + 3, 24}) {
    const TangentFrame frame = frame_at(mesh.positions[centre], Vec3(1, 0, 0), Vec3(0, 0, 1));
    flatten_patch(mesh, topology, triangles_around(topology, centre), frame,
                  template_radius(3, h, h), patch, scratch);
    const auto positions = template_positions(3, h);
    const auto weights = sample(patch, positions);
    for (std::size_t k = 0; k < positions.size(); ++k) {
      const Vec3 target = frame.origin + positions[k].x() * frame.s + positions[k].y() * frame.t;
      const bool on_mesh = target.x() > -kTolerance && target.x() < 4 * h + kTolerance &&
                           target.y() > -kTolerance && target.y() < 4 * h + kTolerance;
      EXPECT_EQ(weights[k].covered(), on_mesh) << "centre " << centre << ", sample " << k;
      if (on_mesh) {
        EXPECT_LT((interpolated_position(mesh, weights[k]) - target).norm(), kWeightTolerance);
      }
    }
  }
}

TEST(PatchFlattening, ReusedScratchGivesTheSameBytesAsAFreshOne) {
  const auto mesh = planar_grid(15, 15, 0.1);
  const geom::MeshTopology topology(mesh);
  PatchScratch reused;
  FlattenedPatch patch;
  for (std::int32_t centre = 0; centre < mesh.num_vertices(); centre += 7) {
    const TangentFrame frame = frame_at(mesh.positions[centre],
                                        Vec3(std::cos(centre), std::sin(centre), 0), Vec3(0, 0, 1));
    const auto seeds = triangles_around(topology, centre);
    flatten_patch(mesh, topology, seeds, frame, 0.45, patch, reused);
    PatchScratch fresh;
    FlattenedPatch reference;
    flatten_patch(mesh, topology, seeds, frame, 0.45, reference, fresh);
    ASSERT_EQ(patch.triangles, reference.triangles);
    ASSERT_EQ(patch.vertices, reference.vertices);
    ASSERT_TRUE(patch.corners == reference.corners);
  }
}

} // namespace
} // namespace texsim::pipelines::surface_synthesis
