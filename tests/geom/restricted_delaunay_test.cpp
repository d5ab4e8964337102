// The retiled mesh (dual of the restricted Voronoi diagram) of relaxed points: a manifold with the
// surface's Euler characteristic, oriented like the surface, independent of triangle and seed
// order, threads and chunk size; square lattices (four cells per Voronoi vertex) split
// consistently by ids; and the Voronoi pieces' edge labels name seeds equidistant from their edges.
#include "core/error.hpp"
#include "core/rng.hpp"
#include "geom/aabb_tree.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/point_relaxation.hpp"
#include "geom/restricted_delaunay.hpp"
#include "geom/restricted_voronoi.hpp"
#include "par/id_runs.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <set>

namespace texsim::geom {
namespace {

par::Comm self() {
  par::Comm comm;
  comm.raw = MPI_COMM_SELF;
  return comm;
}

struct Seeds {
  std::vector<Vec3> points;
  std::vector<std::int64_t> ids;
};

Seeds relaxed_seeds(const TriangleMesh& surface, std::int64_t count, std::uint64_t seed) {
  RelaxationSettings relaxation;
  relaxation.iterations = 15;
  const auto relaxed = relaxed_surface_points(
      self(), DistributedTriangles::from_replicated(self(), surface), count, seed, relaxation);
  Seeds seeds;
  for (std::size_t i = 0; i < relaxed.points.size(); ++i) {
    seeds.points.push_back(relaxed.points[i].position);
    seeds.ids.push_back(relaxed.ids[i]);
  }
  return seeds;
}

/// Checks what a retiling of `surface` by `seeds` must be; returns the mesh.
TriangleMesh check_retiling(const TriangleMesh& surface, const Seeds& seeds) {
  const TriangleMesh mesh = restricted_delaunay(surface, seeds.points, seeds.ids);
  EXPECT_EQ(mesh.positions, seeds.points);
  const MeshTopology topology(mesh);
  const MeshTopology input(surface);
  EXPECT_TRUE(topology.is_manifold());
  EXPECT_TRUE(topology.is_closed());
  EXPECT_TRUE(topology.isolated_vertices().empty());
  EXPECT_EQ(topology.euler_characteristic(), input.euler_characteristic());
  // Each triangle faces the way the surface does where it lies.
  const AabbTree tree(surface);
  int flipped = 0;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const Vec3 normal = (b - a).cross(c - a).normalized();
    const auto nearest = tree.closest_point((a + b + c) / 3.0);
    const Triangle& s = surface.triangles[nearest.triangle];
    const Vec3 surface_normal = (surface.positions[s[1]] - surface.positions[s[0]])
                                    .cross(surface.positions[s[2]] - surface.positions[s[0]])
                                    .normalized();
    flipped += normal.dot(surface_normal) < 0.5 ? 1 : 0;
  }
  EXPECT_EQ(flipped, 0);
  return mesh;
}

/// The triangles of `mesh` as triples of seed ids, in the mesh's order and rotation.
std::vector<std::array<std::int64_t, 3>> id_triangles(const TriangleMesh& mesh,
                                                      const std::vector<std::int64_t>& ids) {
  std::vector<std::array<std::int64_t, 3>> result;
  for (const Triangle& t : mesh.triangles)
    result.push_back({ids[t[0]], ids[t[1]], ids[t[2]]});
  return result;
}

TEST(RestrictedDelaunay, RelaxedPointsOnIcosphereGiveAManifoldSphere) {
  const TriangleMesh sphere = icosphere(4);
  const Seeds seeds = relaxed_seeds(sphere, 1500, 3);
  const TriangleMesh mesh = check_retiling(sphere, seeds);
  EXPECT_EQ(mesh.num_triangles(), 2 * 1500 - 4);
}

TEST(RestrictedDelaunay, RelaxedPointsOnTorusGiveAManifoldTorus) {
  const TriangleMesh ring = torus(1.0, 0.4, 60, 24);
  const Seeds seeds = relaxed_seeds(ring, 1200, 4);
  const TriangleMesh mesh = check_retiling(ring, seeds);
  EXPECT_EQ(mesh.num_triangles(), 2 * 1200);
}

// Noise of 5% of the radius folds the surface into some seeds' 3D Voronoi cells, which then meet
// it in a second, small component elsewhere; without handing those to a neighbour the dual was not
// a manifold for 5 of these 6 seeds.
TEST(RestrictedDelaunay, CellsMeetingANoisySphereTwiceStillGiveAManifoldSphere) {
  const TriangleMesh bumpy = noisy(icosphere(4), 0.05, 3);
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    RelaxationSettings relaxation;
    relaxation.iterations = 10;
    const auto relaxed = relaxed_surface_points(
        self(), DistributedTriangles::from_replicated(self(), bumpy), 1500, seed, relaxation);
    std::vector<Vec3> points;
    for (const auto& p : relaxed.points)
      points.push_back(p.position);
    const MeshTopology topology(restricted_delaunay(bumpy, points, relaxed.ids));
    EXPECT_TRUE(topology.is_manifold()) << "seed " << seed;
    EXPECT_TRUE(topology.is_closed()) << "seed " << seed;
    EXPECT_EQ(topology.euler_characteristic(), 2) << "seed " << seed;
  }
}

TEST(RestrictedDelaunay, IndependentOfTriangleOrderSeedOrderAndThreads) {
  // A surface where some cells meet the surface twice, so the hand-overs are covered too.
  const TriangleMesh ring = noisy(icosphere(4), 0.05, 3);
  const Seeds seeds = relaxed_seeds(ring, 1500, 2);
  const TriangleMesh reference = restricted_delaunay(ring, seeds.points, seeds.ids);

  // Surface triangles reversed and rotated, seeds in a scrambled order with their ids.
  TriangleMesh shuffled = ring;
  std::reverse(shuffled.triangles.begin(), shuffled.triangles.end());
  for (Triangle& t : shuffled.triangles)
    std::rotate(t.begin(), t.begin() + 1, t.end());
  std::vector<std::size_t> order(seeds.points.size());
  std::iota(order.begin(), order.end(), 0);
  const CounterRng rng(9, 1);
  for (std::size_t i = order.size() - 1; i > 0; --i)
    std::swap(order[i], order[std::size_t(rng.uniform(i, 0) * double(i + 1))]);
  Seeds permuted;
  for (const std::size_t i : order) {
    permuted.points.push_back(seeds.points[i]);
    permuted.ids.push_back(seeds.ids[i]);
  }
  const TriangleMesh other = restricted_delaunay(shuffled, permuted.points, permuted.ids);
  EXPECT_EQ(other.positions, permuted.points);
  EXPECT_EQ(id_triangles(other, permuted.ids), id_triangles(reference, seeds.ids));

  const int threads = omp_get_max_threads();
  omp_set_num_threads(3);
  const TriangleMesh threaded = restricted_delaunay(ring, seeds.points, seeds.ids);
  omp_set_num_threads(threads);
  EXPECT_EQ(threaded.triangles, reference.triangles);

  // The pieces taken a chunk of triangles at a time: hand-overs and meetings whose pieces lie in
  // other chunks (one triangle per chunk, chunks that split the pieces of a cell unevenly).
  ASSERT_LT(ring.num_triangles(), kRestrictedDelaunayChunk);
  for (const std::int32_t chunk : {1, 7, 1000})
    EXPECT_EQ(restricted_delaunay(ring, seeds.points, seeds.ids, chunk).triangles,
              reference.triangles)
        << "chunks of " << chunk << " triangles";
}

/// Rank r's even run of `all`.
template <class T> std::vector<T> even_run(const par::Comm& comm, const std::vector<T>& all) {
  const auto size = std::int64_t(all.size());
  return {all.begin() + par::even_run_begin(size, comm.rank, comm.size),
          all.begin() + par::even_run_begin(size, comm.rank + 1, comm.size)};
}

TEST(RestrictedDelaunay, PiecesCutOnEveryRankGiveTheSerialMesh) {
  // Only rank 0 passes the surface; every rank cuts the pieces of its run of triangles against
  // its run of the seeds and a halo of the others'. Chunks of 7 triangles also split each rank's
  // run; the hand-overs of the ring's twice-met cells join pieces from different ranks.
  const par::Comm world = par::world();
  const TriangleMesh ring = noisy(icosphere(4), 0.05, 3);
  const Seeds seeds = relaxed_seeds(ring, 1500, 2);
  // The seeds sorted by x, as runs of ranks: each run is a slab of the ring. The serial mesh of
  // the sorted seeds is the reference (sorting them only renumbers its vertices).
  std::vector<std::size_t> order(seeds.points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](auto a, auto b) { return seeds.points[a].x() < seeds.points[b].x(); });
  std::vector<Vec3> sorted_points;
  std::vector<std::int64_t> sorted_ids;
  for (const auto i : order) {
    sorted_points.push_back(seeds.points[i]);
    sorted_ids.push_back(seeds.ids[i]);
  }
  const TriangleMesh reference = restricted_delaunay(ring, sorted_points, sorted_ids);
  const double spacing = std::sqrt(total_area(ring) / double(seeds.points.size()));
  const auto run_points = even_run(world, sorted_points);
  const auto run_ids = even_run(world, sorted_ids);
  // 6 spacings: the halo suffices; half a spacing does not, and every rank cuts against every
  // seed.
  for (const double halo : {6 * spacing, 0.5 * spacing})
    for (const std::int32_t chunk : {7, kRestrictedDelaunayChunk}) {
      SeedHaloReport report;
      const TriangleMesh distributed =
          restricted_delaunay(world, world.is_root() ? ring : TriangleMesh{}, run_points, run_ids,
                              halo, chunk, &report);
      const bool narrow = halo < spacing;
      EXPECT_EQ(report.every_seed, narrow) << "halo " << halo;
      std::int64_t fewest = report.seeds;
      MPI_Allreduce(MPI_IN_PLACE, &fewest, 1, MPI_INT64_T, MPI_MIN, world.raw);
      if (world.size > 1 && !narrow) {
        EXPECT_LT(fewest, std::int64_t(seeds.points.size())) << "every rank's halo is every seed";
      }
      if (world.is_root()) {
        EXPECT_EQ(distributed.positions, reference.positions);
        EXPECT_EQ(distributed.triangles, reference.triangles)
            << "halo " << halo << ", chunks of " << chunk;
      } else {
        EXPECT_EQ(distributed.num_triangles(), 0);
      }
    }
  // A rank's failure (here: a non-finite seed) is every rank's error, not a hang.
  auto broken = run_points;
  if (!broken.empty())
    broken.front().x() = std::nan("");
  EXPECT_THROW(restricted_delaunay(world, world.is_root() ? ring : TriangleMesh{}, broken, run_ids,
                                   6 * spacing),
               Error);
}

// Seeds at the centres of an m x m lattice of unit squares on a flat square: every inner lattice
// point is a Voronoi vertex of four cells. Each lattice square becomes two triangles, split
// through its smallest-id corner, however the clipping's round-off splits the point, on one rank
// or cut on all.
TEST(RestrictedDelaunay, SquareLatticeSplitsEachSquareThroughItsSmallestId) {
  constexpr int m = 7;
  // Four triangles fanned around a centre no lattice point's line passes through.
  TriangleMesh square;
  square.positions = {Vec3(0, 0, 0), Vec3(m, 0, 0), Vec3(m, m, 0), Vec3(0, m, 0),
                      Vec3(0.5 * m + 0.1234, 0.5 * m + 0.0567, 0)};
  square.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  Seeds seeds;
  const CounterRng rng(13, 1);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      seeds.points.emplace_back(i + 0.5, j + 0.5, 0.0);
      // Scrambled ids, all different.
      seeds.ids.push_back(std::int64_t(rng.bits(std::uint64_t(j * m + i), 0)[0]) * 64 + j * m + i);
    }
  const TriangleMesh mesh = restricted_delaunay(square, seeds.points, seeds.ids);
  ASSERT_EQ(mesh.num_triangles(), 2 * (m - 1) * (m - 1));
  const MeshTopology topology(mesh);
  EXPECT_TRUE(topology.is_manifold());
  EXPECT_EQ(topology.euler_characteristic(), 1);
  std::set<std::array<std::int32_t, 3>> found;
  for (Triangle t : mesh.triangles) {
    const Vec3 normal = (mesh.positions[t[1]] - mesh.positions[t[0]])
                            .cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
    EXPECT_GT(normal.z(), 0.0);
    std::sort(t.begin(), t.end());
    found.insert(t);
  }
  for (int j = 0; j + 1 < m; ++j)
    for (int i = 0; i + 1 < m; ++i) {
      // Corners counter-clockwise; the split joins the smallest-id corner to the opposite one.
      std::array<std::int32_t, 4> corners = {j * m + i, j * m + i + 1, (j + 1) * m + i + 1,
                                             (j + 1) * m + i};
      const auto first = std::min_element(corners.begin(), corners.end(), [&](auto x, auto y) {
        return seeds.ids[std::size_t(x)] < seeds.ids[std::size_t(y)];
      });
      std::rotate(corners.begin(), first, corners.end());
      for (const int k : {1, 2}) {
        std::array<std::int32_t, 3> t = {corners[0], corners[k], corners[k + 1]};
        std::sort(t.begin(), t.end());
        EXPECT_TRUE(found.count(t)) << "square " << i << ", " << j;
      }
    }
  // The same split when every rank cuts a part of the square: the meetings of four cells are the
  // only ones whose points go to rank 0, from each rank that found some.
  const par::Comm world = par::world();
  const TriangleMesh distributed =
      restricted_delaunay(world, world.is_root() ? square : TriangleMesh{},
                          even_run(world, seeds.points), even_run(world, seeds.ids), 3.0, 1);
  if (world.is_root()) {
    EXPECT_EQ(distributed.positions, mesh.positions);
    EXPECT_EQ(distributed.triangles, mesh.triangles);
  }
}

TEST(RestrictedVoronoi, EdgeLabelsNameSeedsEquidistantFromTheirEdges) {
  const TriangleMesh sphere = icosphere(3);
  const Seeds seeds = relaxed_seeds(sphere, 400, 6);
  std::vector<std::int32_t> all(std::size_t(sphere.num_triangles()));
  std::iota(all.begin(), all.end(), 0);
  const auto pieces = restricted_voronoi_pieces(sphere, all, seeds.points, seeds.ids, true);
  std::size_t bisector_edges = 0, boundary_edges = 0;
  for (const VoronoiPiece& piece : pieces) {
    ASSERT_EQ(piece.edge_labels.size(), piece.polygon.size());
    const Triangle& tri = sphere.triangles[piece.triangle];
    const Vec3& own = seeds.points[piece.seed];
    const std::size_t n = piece.polygon.size();
    for (std::size_t k = 0; k < n; ++k) {
      const std::int32_t label = piece.edge_labels[k];
      const Vec3& p = piece.polygon[k];
      const Vec3& q = piece.polygon[(k + 1) % n];
      if (label >= 0) {
        ++bisector_edges;
        const Vec3& other = seeds.points[label];
        for (const Vec3* end : {&p, &q})
          EXPECT_NEAR((*end - own).norm(), (*end - other).norm(), 1e-13);
      } else {
        // On one of the triangle's sides: both ends on the line through two of its corners.
        ++boundary_edges;
        bool on_side = false;
        for (int c = 0; c < 3; ++c) {
          const Vec3& a = sphere.positions[tri[c]];
          const Vec3 side = (sphere.positions[tri[(c + 1) % 3]] - a).normalized();
          on_side =
              on_side || ((p - a).cross(side).norm() < 1e-13 && (q - a).cross(side).norm() < 1e-13);
        }
        EXPECT_TRUE(on_side);
      }
    }
  }
  EXPECT_GT(bisector_edges, 1000u);
  EXPECT_GT(boundary_edges, 1000u);
  const auto without = restricted_voronoi_pieces(sphere, all, seeds.points, seeds.ids, false);
  ASSERT_EQ(without.size(), pieces.size());
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    EXPECT_TRUE(without[k].edge_labels.empty());
    EXPECT_EQ(without[k].area, pieces[k].area);
  }
}

} // namespace
} // namespace texsim::geom
