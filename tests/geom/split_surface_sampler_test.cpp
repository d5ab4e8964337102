// A field on a surface split over ranks, read at rank 0's points: the values are those of the
// nearest triangle of the whole surface by AabbTree::nearest_triangle's rule (brute force over
// every triangle), ties at shared edges and corners included, so the bytes do not depend on the
// rank count; away from ties they are SurfaceFieldSampler's (CGAL's closest point).
#include "core/error.hpp"
#include "core/rng.hpp"
#include "geom/aabb_tree.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/split_surface_sampler.hpp"
#include "geom/surface_field_sampler.hpp"
#include "par/comm.hpp"
#include "par/id_runs.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace texsim::geom {
namespace {

std::array<double, 3> field_at(const Vec3& p) {
  return {p.x() + 2 * p.y() * p.z(), std::sin(3 * p.z()), p.y() - p.x() * p.x()};
}

/// Rank r's even run of the triangles in id order, with the vertices they use (renumbered in
/// increasing order, as LocalSurface numbers them); with three ranks, rank 1 holds none.
struct Share {
  TriangleMesh mesh;
  std::vector<std::int64_t> triangle_ids;
  std::vector<std::array<double, 3>> values;
};

Share share_of(const par::Comm& comm, const TriangleMesh& whole) {
  const int parts = comm.size == 3 ? 2 : comm.size;
  const int part = comm.size == 3 ? (comm.rank == 0 ? 0 : comm.rank - 1) : comm.rank;
  Share share;
  if (comm.size == 3 && comm.rank == 1)
    return share;
  const auto count = std::int64_t(whole.triangles.size());
  std::vector<std::int32_t> local(whole.positions.size(), -1);
  for (auto t = par::even_run_begin(count, part, parts);
       t < par::even_run_begin(count, part + 1, parts); ++t)
    for (const auto v : whole.triangles[std::size_t(t)])
      local[std::size_t(v)] = 0;
  for (std::size_t v = 0; v < local.size(); ++v)
    if (local[v] == 0) {
      local[v] = std::int32_t(share.mesh.positions.size());
      share.mesh.positions.push_back(whole.positions[v]);
      share.values.push_back(field_at(whole.positions[v]));
    }
  for (auto t = par::even_run_begin(count, part, parts);
       t < par::even_run_begin(count, part + 1, parts); ++t) {
    const auto& c = whole.triangles[std::size_t(t)];
    share.mesh.triangles.push_back(
        {local[std::size_t(c[0])], local[std::size_t(c[1])], local[std::size_t(c[2])]});
    share.triangle_ids.push_back(t);
  }
  return share;
}

/// The smallest (squared distance, id) over every triangle, each projected alone.
struct BruteForce {
  explicit BruteForce(const TriangleMesh& whole) : whole_(whole) {
    for (const auto& t : whole.triangles) {
      TriangleMesh one;
      one.positions = {whole.positions[t[0]], whole.positions[t[1]], whole.positions[t[2]]};
      one.triangles = {{0, 1, 2}};
      trees_.emplace_back(one);
    }
  }
  /// The field at `p` and how many triangles tie for nearest.
  std::pair<std::array<double, 3>, int> at(const Vec3& p) const {
    NearestTriangle best{p, -1, std::numeric_limits<double>::infinity()};
    int tied = 0;
    for (std::size_t t = 0; t < trees_.size(); ++t) {
      const auto candidate = trees_[t].nearest_triangle(p);
      if (candidate.squared_distance < best.squared_distance) {
        best = {candidate.point, std::int32_t(t), candidate.squared_distance};
        tied = 1;
      } else if (candidate.squared_distance == best.squared_distance) {
        ++tied;
      }
    }
    const auto& t = whole_.triangles[std::size_t(best.triangle)];
    const auto w = barycentric_weights(whole_.positions[t[0]], whole_.positions[t[1]],
                                       whole_.positions[t[2]], best.point);
    std::array<double, 3> value{};
    for (std::size_t k = 0; k < 3; ++k)
      value[k] = w[0] * field_at(whole_.positions[t[0]])[k] +
                 w[1] * field_at(whole_.positions[t[1]])[k] +
                 w[2] * field_at(whole_.positions[t[2]])[k];
    return {value, tied};
  }

private:
  const TriangleMesh& whole_;
  std::vector<AabbTree> trees_;
};

/// Random points near the unit sphere, every tenth far from it.
std::vector<Vec3> around_sphere(std::uint64_t count) {
  const CounterRng rng(19, 3);
  std::vector<Vec3> points;
  for (std::uint64_t i = 0; i < count; ++i) {
    const Vec3 direction =
        Vec3(rng.normal(i, 0, 0), rng.normal(i, 0, 1), rng.normal(i, 0, 2)).normalized();
    points.push_back((i % 10 == 0 ? 4.0 : rng.uniform(0.8, 1.2, i, 1)) * direction);
  }
  return points;
}

TEST(SplitSurfaceSampler, EqualsBruteForceOnANoisySphereAndAwayFromTiesTheWholeTreesValues) {
  const par::Comm comm = par::world();
  const TriangleMesh whole = noisy(icosphere(3), 0.05, 5);
  const Share share = share_of(comm, whole);
  const auto points = comm.rank == 0 ? around_sphere(400) : std::vector<Vec3>{};
  const auto sampled =
      sample_split_surface(comm, share.mesh, share.triangle_ids, share.values, points);
  if (comm.rank != 0) {
    EXPECT_TRUE(sampled.empty());
    return;
  }
  ASSERT_EQ(sampled.size(), points.size());
  const BruteForce brute(whole);
  std::vector<std::vector<double>> fields(3);
  for (const auto& p : whole.positions)
    for (std::size_t k = 0; k < 3; ++k)
      fields[k].push_back(field_at(p)[k]);
  const SurfaceFieldSampler whole_tree(whole, fields);
  const auto cgal = whole_tree.sample_all(points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [expected, tied] = brute.at(points[i]);
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(sampled[i][k], expected[k]) << "point " << i << " field " << k;
      if (tied == 1) {
        EXPECT_EQ(sampled[i][k], cgal.values[k][i]) << "point " << i << " field " << k;
      }
    }
  }
}

TEST(SplitSurfaceSampler, PointsAboveSharedEdgesAndCornersTakeTheLowestIdOfTheTiedTriangles) {
  const par::Comm comm = par::world();
  const TriangleMesh whole = plane(Vec3(1, 1, 0), 6);
  const Share share = share_of(comm, whole);
  // Above every vertex and every edge midpoint of the grid, at heights 0 and 0.3: each is as
  // near to two or more triangles.
  std::vector<Vec3> points;
  if (comm.rank == 0)
    for (const double height : {0.0, 0.3})
      for (int i = 0; i <= 12; ++i)
        for (int j = 0; j <= 12; ++j)
          if (i % 2 == 0 || j % 2 == 0)
            points.emplace_back(i / 12.0, j / 12.0, height);
  const auto sampled =
      sample_split_surface(comm, share.mesh, share.triangle_ids, share.values, points);
  if (comm.rank != 0)
    return;
  const BruteForce brute(whole);
  int ties = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [expected, tied] = brute.at(points[i]);
    ties += tied > 1;
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_EQ(sampled[i][k], expected[k]) << "point " << i << " field " << k;
  }
  EXPECT_GT(ties, int(points.size()) / 2);
}

TEST(SplitSurfaceSampler, NoTriangleOnAnyRankIsAnErrorOnEveryRank) {
  const par::Comm comm = par::world();
  const std::vector<Vec3> points{Vec3(0, 0, 0)};
  EXPECT_THROW(sample_split_surface(comm, {}, {}, {}, points), Error);
}

} // namespace
} // namespace texsim::geom
