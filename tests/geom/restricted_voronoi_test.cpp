#include "core/error.hpp"
#include "core/rng.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/restricted_voronoi.hpp"
#include "support/test_data.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

namespace texsim::geom {
namespace {

struct SurfaceSample {
  Vec3 point;
  std::int32_t triangle;
};

/// `count` points uniformly distributed over the surface (area-weighted triangle choice, uniform
/// barycentric point), reproducible from (seed, stream).
std::vector<SurfaceSample> sample_surface(const TriangleMesh& mesh, std::int64_t count,
                                          std::uint64_t seed, std::uint32_t stream) {
  const auto areas = triangle_areas(mesh);
  std::vector<double> cumulative(areas.size());
  std::partial_sum(areas.begin(), areas.end(), cumulative.begin());
  const CounterRng rng(seed, stream);
  std::vector<SurfaceSample> samples;
  samples.reserve(static_cast<std::size_t>(count));
  for (std::int64_t s = 0; s < count; ++s) {
    const double pick = rng.uniform(s, 0, 0) * cumulative.back();
    const auto t = static_cast<std::int32_t>(std::min<std::ptrdiff_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
        mesh.num_triangles() - 1));
    const double r = std::sqrt(rng.uniform(s, 0, 1));
    const double u = rng.uniform(s, 0, 2);
    const auto& tri = mesh.triangles[t];
    samples.push_back({(1.0 - r) * mesh.positions[tri[0]] + r * (1.0 - u) * mesh.positions[tri[1]] +
                           r * u * mesh.positions[tri[2]],
                       t});
  }
  return samples;
}

std::vector<Vec3> points_of(const std::vector<SurfaceSample>& samples) {
  std::vector<Vec3> points;
  for (const auto& s : samples)
    points.push_back(s.point);
  return points;
}

std::vector<Vec3> random_directions(std::int64_t count, double radius, std::uint64_t seed) {
  const CounterRng rng(seed, 1);
  std::vector<Vec3> points;
  for (std::int64_t i = 0; i < count; ++i)
    points.push_back(
        radius * Vec3(rng.normal(i, 0, 0), rng.normal(i, 0, 1), rng.normal(i, 0, 2)).normalized());
  return points;
}

std::vector<std::int32_t> all_triangles(const TriangleMesh& mesh) {
  std::vector<std::int32_t> ids(static_cast<std::size_t>(mesh.num_triangles()));
  std::iota(ids.begin(), ids.end(), 0);
  return ids;
}

std::vector<std::int64_t> iota_ids(std::size_t count, std::int64_t first = 0) {
  std::vector<std::int64_t> ids(count);
  std::iota(ids.begin(), ids.end(), first);
  return ids;
}

/// Brute force over all seeds: the squared distance from p to its nearest seed.
double nearest_distance2(const Vec3& p, const std::vector<Vec3>& seeds) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& s : seeds)
    best = std::min(best, (p - s).squaredNorm());
  return best;
}

double bounding_diagonal(const TriangleMesh& mesh) {
  Vec3 lo = mesh.positions[0], hi = mesh.positions[0];
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

/// The properties every exact RVD has, checked against brute force. Pieces computed with
/// keep_polygons over all triangles; every `vertex_stride`-th piece has its vertices checked.
void check_rvd(const TriangleMesh& mesh, const std::vector<Vec3>& seeds,
               const std::vector<VoronoiPiece>& pieces, int vertex_stride,
               const std::vector<SurfaceSample>& probes) {
  const double scale = bounding_diagonal(mesh);

  // Sorted by (triangle, seed id = index here), and pieces of each triangle sum to its area.
  for (std::size_t p = 1; p < pieces.size(); ++p) {
    ASSERT_TRUE(
        pieces[p - 1].triangle < pieces[p].triangle ||
        (pieces[p - 1].triangle == pieces[p].triangle && pieces[p - 1].seed < pieces[p].seed))
        << "piece " << p;
  }
  double total = 0.0;
  std::vector<double> per_triangle(static_cast<std::size_t>(mesh.num_triangles()), 0.0);
  for (const auto& piece : pieces) {
    EXPECT_GT(piece.area, 0.0);
    total += piece.area;
    per_triangle[piece.triangle] += piece.area;
  }
  EXPECT_NEAR(total, total_area(mesh), 1e-9 * total_area(mesh));
  const auto areas = triangle_areas(mesh);
  int bad_triangles = 0;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t)
    bad_triangles += std::abs(per_triangle[t] - areas[t]) > 1e-9 * areas[t] + 1e-15 * scale * scale;
  EXPECT_EQ(bad_triangles, 0);

  // Every polygon vertex is at least as close to its seed as to every other seed.
  int far_vertices = 0;
  for (std::size_t p = 0; p < pieces.size(); p += vertex_stride) {
    const auto& piece = pieces[p];
    EXPECT_GE(piece.polygon.size(), 3u);
    for (const Vec3& v : piece.polygon) {
      const double own = (v - seeds[piece.seed]).norm();
      if (own > std::sqrt(nearest_distance2(v, seeds)) + 1e-9 * scale)
        ++far_vertices;
    }
  }
  EXPECT_EQ(far_vertices, 0);

  // The border between i and j has the same length seen from both cells.
  std::map<std::pair<std::int32_t, std::int32_t>, double> border;
  for (const auto& piece : pieces) {
    for (std::size_t b = 0; b < piece.borders.size(); ++b) {
      const auto [j, length] = piece.borders[b];
      EXPECT_NE(j, piece.seed);
      EXPECT_GT(length, 0.0);
      if (b > 0) {
        EXPECT_LT(piece.borders[b - 1].first, j) << "borders not sorted by seed";
      }
      border[{piece.seed, j}] += length;
    }
  }
  int asymmetric = 0;
  for (const auto& [key, length] : border) {
    const auto other = border.find({key.second, key.first});
    const double seen_back = other == border.end() ? 0.0 : other->second;
    if (std::abs(length - seen_back) > 1e-9 * std::max(length, seen_back) + 1e-14 * scale)
      ++asymmetric;
  }
  EXPECT_EQ(asymmetric, 0) << "of " << border.size() << " borders";
  EXPECT_GT(border.size(), 3 * seeds.size()); // every cell has neighbours

  // A random surface point lies in a piece of the brute-force nearest seed.
  int misplaced = 0, unowned = 0;
  for (const auto& probe : probes) {
    const auto& tri = mesh.triangles[probe.triangle];
    const Vec3 normal = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
                            .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    const auto first = std::lower_bound(
        pieces.begin(), pieces.end(), probe.triangle,
        [](const VoronoiPiece& piece, std::int32_t t) { return piece.triangle < t; });
    std::int32_t owner = -1;
    for (auto it = first; it != pieces.end() && it->triangle == probe.triangle; ++it) {
      bool inside = true;
      const std::size_t n = it->polygon.size();
      for (std::size_t k = 0; k < n && inside; ++k) {
        const Vec3& a = it->polygon[k];
        const Vec3& b = it->polygon[(k + 1) % n];
        inside = (b - a).cross(probe.point - a).dot(normal) >= -1e-12 * normal.norm() * scale;
      }
      if (inside) {
        owner = it->seed;
        break;
      }
    }
    if (owner < 0) {
      ++unowned;
      continue;
    }
    const double own = (probe.point - seeds[owner]).norm();
    misplaced += own > std::sqrt(nearest_distance2(probe.point, seeds)) + 1e-9 * scale;
  }
  EXPECT_EQ(unowned, 0);
  EXPECT_EQ(misplaced, 0) << "of " << probes.size() << " probes";
}

/// Pieces equal to the bit, with seed indices of each side mapped to global ids.
void expect_identical(const std::vector<VoronoiPiece>& a, std::span<const std::int64_t> a_ids,
                      const std::vector<VoronoiPiece>& b, std::span<const std::int64_t> b_ids) {
  ASSERT_EQ(a.size(), b.size());
  auto mapped_borders = [](const VoronoiPiece& piece, std::span<const std::int64_t> ids) {
    std::vector<std::pair<std::int64_t, double>> borders;
    for (const auto& [j, length] : piece.borders)
      borders.emplace_back(ids[j], length);
    std::sort(borders.begin(), borders.end());
    return borders;
  };
  int different = 0;
  for (std::size_t p = 0; p < a.size(); ++p) {
    const bool same = a[p].triangle == b[p].triangle && a_ids[a[p].seed] == b_ids[b[p].seed] &&
                      a[p].area == b[p].area &&
                      mapped_borders(a[p], a_ids) == mapped_borders(b[p], b_ids) &&
                      a[p].polygon == b[p].polygon;
    different += !same;
  }
  EXPECT_EQ(different, 0) << "of " << a.size() << " pieces";
}

TEST(RestrictedVoronoi, IcosphereWithRandomSeedsIsExact) {
  const auto mesh = icosphere(3);
  const auto seeds = random_directions(2000, 1.0, 11);
  const auto ids = iota_ids(seeds.size());
  const auto triangles = all_triangles(mesh);
  const auto pieces = restricted_voronoi_pieces(mesh, triangles, seeds, ids, true);
  EXPECT_GT(pieces.size(), seeds.size());
  check_rvd(mesh, seeds, pieces, 1, sample_surface(mesh, 3000, 5, 2));

  // Every seed lies close to the sphere, so every seed owns some area.
  std::vector<double> cell_area(seeds.size(), 0.0);
  for (const auto& piece : pieces)
    cell_area[piece.seed] += piece.area;
  EXPECT_EQ(std::count(cell_area.begin(), cell_area.end(), 0.0), 0);
}

TEST(RestrictedVoronoiOnRealData, BunnyWithRandomSurfaceSeedsIsExact) {
  const std::string name = "meshes/bunny00.off";
  const auto path = test::real_data(name);
  if (path.empty())
    GTEST_SKIP() << test::missing_data_message(name);
  const auto mesh = read_mesh(path);
  const auto seeds = points_of(sample_surface(mesh, 5000, 21, 1));
  const auto ids = iota_ids(seeds.size());
  const auto pieces = restricted_voronoi_pieces(mesh, all_triangles(mesh), seeds, ids, true);
  check_rvd(mesh, seeds, pieces, 4, sample_surface(mesh, 3000, 22, 2));
}

/// The unit square z = 0 as two triangles, with seeds at the centres of an n x n grid of cells.
struct LatticeSquare {
  TriangleMesh mesh;
  std::vector<Vec3> seeds;
  int n;
  double h;
};

LatticeSquare lattice_square(int n) {
  LatticeSquare square;
  square.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  square.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  square.n = n;
  square.h = 1.0 / n;
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a)
      square.seeds.emplace_back((a + 0.5) * square.h, (b + 0.5) * square.h, 0.0);
  return square;
}

TEST(RestrictedVoronoi, SquareLatticeCellsAreSquaresWithFourBorders) {
  for (const int n : {8, 7}) { // 1/8 is exact in binary, 1/7 is not
    const auto square = lattice_square(n);
    const double h = square.h;
    const auto ids = iota_ids(square.seeds.size());
    const auto pieces =
        restricted_voronoi_pieces(square.mesh, all_triangles(square.mesh), square.seeds, ids, true);
    std::vector<double> area(square.seeds.size(), 0.0);
    std::vector<std::map<std::int32_t, double>> borders(square.seeds.size());
    for (const auto& piece : pieces) {
      area[piece.seed] += piece.area;
      for (const auto& [j, length] : piece.borders)
        borders[piece.seed][j] += length;
    }
    for (int b = 0; b < n; ++b) {
      for (int a = 0; a < n; ++a) {
        const int i = b * n + a;
        EXPECT_NEAR(area[i], h * h, 1e-14) << "n " << n << " cell " << a << "," << b;
        // Borders only with the axis neighbours, each a whole side h; the diagonal neighbours
        // touch in a point and must not appear even as round-off slivers of length > 1e-12.
        std::map<std::int32_t, double> expected;
        if (a > 0)
          expected[i - 1] = h;
        if (a + 1 < n)
          expected[i + 1] = h;
        if (b > 0)
          expected[i - n] = h;
        if (b + 1 < n)
          expected[i + n] = h;
        std::map<std::int32_t, double> found;
        for (const auto& [j, length] : borders[i])
          if (length > 1e-12)
            found[j] = length;
        ASSERT_EQ(found.size(), expected.size()) << "n " << n << " cell " << a << "," << b;
        for (const auto& [j, length] : expected) {
          ASSERT_TRUE(found.count(j)) << "cell " << a << "," << b << " misses neighbour " << j;
          EXPECT_NEAR(found[j], length, 1e-14);
        }
      }
    }
  }
}

TEST(RestrictedVoronoi, TiesAreBrokenByIdNotBySeedOrderOrExtraSeeds) {
  // The lattice is full of exact distance ties: the pieces must not depend on the seeds' order in
  // the span, nor on far seeds that change the k-d tree and the k nearest lists.
  const auto square = lattice_square(8);
  const auto ids = iota_ids(square.seeds.size());
  const auto triangles = all_triangles(square.mesh);
  const auto reference = restricted_voronoi_pieces(square.mesh, triangles, square.seeds, ids, true);

  std::vector<std::size_t> permutation(square.seeds.size());
  std::iota(permutation.begin(), permutation.end(), 0);
  std::reverse(permutation.begin(), permutation.end());
  std::rotate(permutation.begin(), permutation.begin() + 13, permutation.end());
  std::vector<Vec3> shuffled;
  std::vector<std::int64_t> shuffled_ids;
  for (const std::size_t i : permutation) {
    shuffled.push_back(square.seeds[i]);
    shuffled_ids.push_back(ids[i]);
  }
  // Far seeds: mirror pairs above and below the square at the same height (ties again), and some
  // far out in the plane; their ids interleave with the lattice ids.
  for (int k = 0; k < 40; ++k) {
    const double x = 0.1 * (k % 10), y = 0.25 * (k / 10);
    shuffled.emplace_back(x, y, 3.0);
    shuffled_ids.push_back(1000 - 2 * k);
    shuffled.emplace_back(x, y, -3.0);
    shuffled_ids.push_back(-5 - 3 * k);
    shuffled.emplace_back(5.0 + x, y, 0.0);
    shuffled_ids.push_back(100 + 7 * k);
  }
  const auto pieces =
      restricted_voronoi_pieces(square.mesh, triangles, shuffled, shuffled_ids, true);
  expect_identical(reference, ids, pieces, shuffled_ids);
}

TEST(RestrictedVoronoi, CellRingedByMoreEquidistantSeedsThanTheFirstQueryHolds) {
  // 48 integer points lie on the circle x^2 + y^2 = 5525 (5^2 13 17): around a seed at the
  // origin they are exact distance ties that straddle the first k-nearest query, and every one of
  // them cuts an edge of the central cell. A seed list taken past the ties' end in one query and
  // continued in another would skip some of them.
  TriangleMesh mesh;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  const double unit = 1.0 / 256.0;
  std::vector<Vec3> seeds = {Vec3::Zero()};
  std::vector<std::int32_t> ring;
  for (int x = -75; x <= 75; ++x) {
    for (int y = -75; y <= 75; ++y) {
      if (x * x + y * y == 5525) {
        ring.push_back(static_cast<std::int32_t>(seeds.size()));
        seeds.emplace_back(x * unit, y * unit, 0.0);
      }
    }
  }
  ASSERT_EQ(ring.size(), 48u);
  for (int x = -4; x <= 4; ++x)
    for (int y = -4; y <= 4; ++y)
      if (x * x + y * y >= 9)
        seeds.emplace_back(0.25 * x, 0.25 * y, 0.0);
  const auto ids = iota_ids(seeds.size(), 100);
  const auto pieces = restricted_voronoi_pieces(mesh, all_triangles(mesh), seeds, ids, true);

  std::map<std::int32_t, double> centre_borders;
  double total = 0.0;
  int far_vertices = 0;
  for (const auto& piece : pieces) {
    total += piece.area;
    if (piece.seed == 0)
      for (const auto& [j, length] : piece.borders)
        centre_borders[j] += length;
    for (const Vec3& v : piece.polygon)
      far_vertices +=
          (v - seeds[piece.seed]).norm() > std::sqrt(nearest_distance2(v, seeds)) + 1e-12;
  }
  EXPECT_NEAR(total, 4.0, 1e-12);
  EXPECT_EQ(far_vertices, 0);
  ASSERT_EQ(centre_borders.size(), ring.size());
  for (const std::int32_t j : ring)
    EXPECT_TRUE(centre_borders.count(j)) << "ring seed " << j << " cuts no edge of the centre cell";
}

TEST(RestrictedVoronoi, PieceInTheBisectorOfMirrorSeedsGoesToTheSmallerId) {
  // Seeds mirrored across the plane of the square: every point of the square is equidistant from
  // both seeds of a pair, so each site's square belongs to the one with the smaller id (upper or
  // lower, alternating), and never to both.
  const auto square = lattice_square(4);
  std::vector<Vec3> seeds;
  std::vector<std::int64_t> ids;
  for (std::size_t k = 0; k < square.seeds.size(); ++k) {
    const std::int64_t even = 2 * static_cast<std::int64_t>(k);
    seeds.push_back(square.seeds[k] + Vec3(0, 0, 0.05));
    ids.push_back(k % 3 == 0 ? even : even + 1);
    seeds.push_back(square.seeds[k] - Vec3(0, 0, 0.05));
    ids.push_back(k % 3 == 0 ? even + 1 : even);
  }
  const auto pieces =
      restricted_voronoi_pieces(square.mesh, all_triangles(square.mesh), seeds, ids, false);
  std::vector<double> area(seeds.size(), 0.0);
  for (const auto& piece : pieces)
    area[piece.seed] += piece.area;
  for (std::size_t k = 0; k < square.seeds.size(); ++k) {
    const std::size_t owner = ids[2 * k] < ids[2 * k + 1] ? 2 * k : 2 * k + 1;
    EXPECT_NEAR(area[owner], square.h * square.h, 1e-14) << "site " << k;
    EXPECT_EQ(area[owner ^ 1], 0.0) << "site " << k;
  }
}

TEST(RestrictedVoronoi, ExtraFarSeedsGiveBitIdenticalPieces) {
  const auto mesh = icosphere(3);
  const auto seeds = random_directions(2000, 1.0, 11);
  const auto ids = iota_ids(seeds.size());
  const auto triangles = all_triangles(mesh);
  const auto reference = restricted_voronoi_pieces(mesh, triangles, seeds, ids, true);

  // Appended, so the seed indices of the original seeds do not change. Seeds on a sphere of radius
  // 1.5 are closer to many cells than their 20th neighbour would be on a coarser sampling, but
  // farther than any security radius here.
  auto extended = seeds;
  for (const Vec3& p : random_directions(500, 1.5, 12))
    extended.push_back(p);
  for (const Vec3& p : random_directions(100, 10.0, 13))
    extended.push_back(p);
  const auto extended_ids = iota_ids(extended.size());
  const auto pieces = restricted_voronoi_pieces(mesh, triangles, extended, extended_ids, true);
  expect_identical(reference, ids, pieces, extended_ids);
}

/// Distance from p to the closed triangle (a, b, c).
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 normal = (b - a).cross(c - a).normalized();
  const Vec3 q = p - normal.dot(p - a) * normal;
  const std::array<Vec3, 3> corners = {a, b, c};
  bool inside = true;
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const Vec3& u = corners[k];
    const Vec3& v = corners[(k + 1) % 3];
    inside = inside && (v - u).cross(q - u).dot(normal) >= 0.0;
    const double s = std::clamp((p - u).dot(v - u) / (v - u).squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - (u + s * (v - u))).norm());
  }
  return inside ? std::abs(normal.dot(p - a)) : best;
}

/// A rank's part of the sphere (the cap z > 0.6, listed in reverse order) with the seeds within
/// 3 rho of its triangles gives the same pieces, to the bit, as the whole mesh with all seeds.
void expect_part_with_halo_equals_whole(int level, std::int64_t num_seeds) {
  const auto mesh = icosphere(level);
  const auto seeds = random_directions(num_seeds, 1.0, 11);
  const auto ids = iota_ids(seeds.size());
  const auto whole = restricted_voronoi_pieces(mesh, all_triangles(mesh), seeds, ids, true);

  // rho: the largest distance from the surface to its nearest seed (a polygon vertex is farthest).
  double rho = 0.0;
  for (const auto& piece : whole)
    for (const Vec3& v : piece.polygon)
      rho = std::max(rho, (v - seeds[piece.seed]).norm());

  std::vector<std::int32_t> part;
  for (std::int32_t t = mesh.num_triangles() - 1; t >= 0; --t) {
    const auto& tri = mesh.triangles[t];
    if ((mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]).z() > 3 * 0.6)
      part.push_back(t);
  }
  ASSERT_GT(part.size(), 3u);
  std::vector<Vec3> halo;
  std::vector<std::int64_t> halo_ids;
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    bool near = false;
    for (const std::int32_t t : part) {
      const auto& tri = mesh.triangles[t];
      near = near || distance_to_triangle(seeds[i], mesh.positions[tri[0]], mesh.positions[tri[1]],
                                          mesh.positions[tri[2]]) <= 3 * rho;
    }
    if (near) {
      halo.push_back(seeds[i]);
      halo_ids.push_back(ids[i]);
    }
  }
  ASSERT_LT(halo.size(), seeds.size() * 2 / 3);
  const auto pieces = restricted_voronoi_pieces(mesh, part, halo, halo_ids, true);
  std::vector<VoronoiPiece> expected;
  std::sort(part.begin(), part.end());
  for (const auto& piece : whole)
    if (std::binary_search(part.begin(), part.end(), piece.triangle))
      expected.push_back(piece);
  expect_identical(expected, ids, pieces, halo_ids);
}

TEST(RestrictedVoronoi, PartWithHaloEqualsTheWhole) {
  expect_part_with_halo_equals_whole(3, 2000);
  // Triangles much larger than the cells: the first clips of a piece come from seeds the halo
  // does not hold.
  expect_part_with_halo_equals_whole(1, 4000);
}

TEST(RestrictedVoronoi, ThreadCountDoesNotMatter) {
  const auto mesh = icosphere(3);
  const auto seeds = random_directions(2000, 1.0, 11);
  const auto ids = iota_ids(seeds.size());
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto serial = restricted_voronoi_pieces(mesh, all_triangles(mesh), seeds, ids, true);
  for (const int count : {2, 3}) {
    omp_set_num_threads(count);
    const auto again = restricted_voronoi_pieces(mesh, all_triangles(mesh), seeds, ids, true);
    expect_identical(serial, ids, again, ids);
  }
  omp_set_num_threads(threads);
}

TEST(RestrictedVoronoi, ThrowsWhenTheSeedsCannotCertifyACell) {
  // 2 x 2 lattice: a corner cell's radius is h / sqrt(2) with h = 1/2, and no seed lies farther
  // than twice that from its seed, so no cell can be certified from these seeds alone.
  const auto square = lattice_square(2);
  const auto ids = iota_ids(square.seeds.size());
  EXPECT_THROW(
      restricted_voronoi_pieces(square.mesh, all_triangles(square.mesh), square.seeds, ids, false),
      Error);
  // With the next ring of a 4 x 4 lattice present, the same corner cells are certified.
  const auto larger = lattice_square(4);
  EXPECT_NO_THROW(restricted_voronoi_pieces(larger.mesh, all_triangles(larger.mesh), larger.seeds,
                                            iota_ids(larger.seeds.size()), false));
}

TEST(RestrictedVoronoi, RejectsBadArguments) {
  const auto square = lattice_square(4);
  const auto ids = iota_ids(square.seeds.size());
  const std::vector<std::int32_t> out_of_range = {0, 2};
  EXPECT_THROW(restricted_voronoi_pieces(square.mesh, out_of_range, square.seeds, ids, false),
               Error);
  const std::vector<std::int32_t> repeated = {1, 1};
  EXPECT_THROW(restricted_voronoi_pieces(square.mesh, repeated, square.seeds, ids, false), Error);
  auto same_ids = ids;
  same_ids[3] = same_ids[5];
  EXPECT_THROW(restricted_voronoi_pieces(square.mesh, all_triangles(square.mesh), square.seeds,
                                         same_ids, false),
               Error);
  EXPECT_TRUE(
      restricted_voronoi_pieces(square.mesh, std::vector<std::int32_t>{}, square.seeds, ids, false)
          .empty());
}

TEST(RestrictedVoronoiOnRealData, BunnyHundredThousandSeedsTimingAtOneAndTwoThreads) {
  const std::string name = "meshes/bunny00.off";
  const auto path = test::real_data(name);
  if (path.empty())
    GTEST_SKIP() << test::missing_data_message(name);
  const auto mesh = read_mesh(path);
  const auto seeds = points_of(sample_surface(mesh, 100000, 31, 1));
  const auto ids = iota_ids(seeds.size());
  const auto triangles = all_triangles(mesh);
  const int threads = omp_get_max_threads();
  std::vector<VoronoiPiece> first;
  for (const int count : {1, 2}) {
    omp_set_num_threads(count);
    const auto start = std::chrono::steady_clock::now();
    const auto pieces = restricted_voronoi_pieces(mesh, triangles, seeds, ids, false);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    double total = 0.0;
    std::size_t borders = 0;
    for (const auto& piece : pieces) {
      total += piece.area;
      borders += piece.borders.size();
    }
    EXPECT_NEAR(total, total_area(mesh), 1e-9 * total_area(mesh));
    std::printf("[ timing   ] bunny %d triangles, %zu seeds, %d thread(s): %.3f s, %zu pieces, "
                "%zu borders\n",
                mesh.num_triangles(), seeds.size(), count, seconds, pieces.size(), borders);
    if (first.empty())
      first = pieces;
    else
      expect_identical(first, ids, pieces, ids);
  }
  omp_set_num_threads(threads);
}

} // namespace
} // namespace texsim::geom
