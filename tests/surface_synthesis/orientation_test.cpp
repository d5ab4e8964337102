// Texture orientation: the exact per-vertex minimiser against a 0.01 degree scan, energy that never
// rises over sweeps, multiples of 90 degrees fixed for 4-way and moved for 2-way symmetry, a
// relaxed sphere that is smooth almost everywhere, the same bits on any rank and thread count, and
// inherited directions that reproduce a smooth parent field.
#include "core/error.hpp"
#include "core/rng.hpp"
#include "geom/aabb_tree.hpp"
#include "geom/distributed_triangles.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_topology.hpp"
#include "par/allgather_runs.hpp"
#include "pipelines/surface_synthesis/orientation_field.hpp"
#include "pipelines/surface_synthesis/orientation_relaxation.hpp"
#include "pipelines/surface_synthesis/parent_faces.hpp"
#include "pipelines/surface_synthesis/run_star.hpp"
#include "support/gather_by_id.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>
#include <optional>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

/// A mesh level as the relaxation sees it.
struct Level {
  geom::TriangleMesh mesh;
  geom::MeshTopology topology;
  std::vector<geom::Vec3> normals;

  explicit Level(geom::TriangleMesh m)
      : mesh(std::move(m)), topology(mesh), normals(geom::vertex_normals(mesh)) {}
};

/// Equal runs of vertex ids per rank.
std::vector<std::int64_t> equal_runs(const par::Comm& comm, std::int64_t count) {
  std::vector<std::int64_t> offsets(comm.size + 1);
  for (int r = 0; r <= comm.size; ++r)
    offsets[r] = count * r / comm.size;
  return offsets;
}

/// The 1-rings of this rank's run of `level` under equal_runs.
geom::CsrAdjacency own_rings(const par::Comm& comm, const Level& level) {
  const auto runs = equal_runs(comm, level.topology.num_vertices());
  return run_rings(level.mesh, runs[comm.rank], runs[comm.rank + 1] - runs[comm.rank]);
}

/// This rank's run of per-vertex `records` under equal_runs.
template <typename Record>
std::vector<Record> own_run(const par::Comm& comm, const std::vector<Record>& records) {
  const auto runs = equal_runs(comm, std::int64_t(records.size()));
  return {records.begin() + runs[comm.rank], records.begin() + runs[comm.rank + 1]};
}

/// Every rank's run of directions (under equal_runs of `count`) on every rank.
std::vector<geom::Vec3> whole_level(const par::Comm& comm, const std::vector<geom::Vec3>& run,
                                    std::int64_t count) {
  std::vector<geom::Vec3> all(static_cast<std::size_t>(count));
  const auto runs = equal_runs(comm, count);
  std::copy(run.begin(), run.end(), all.begin() + runs[comm.rank]);
  par::allgather_runs(comm, runs, all.data(), 3, MPI_DOUBLE);
  return all;
}

/// Parent faces of `fine`'s vertices on `coarse`: the triangle of the closest point and its
/// barycentric weights.
std::vector<ParentFace> closest_parent_faces(const Level& fine, const Level& coarse) {
  const geom::AabbTree tree(coarse.mesh);
  std::vector<ParentFace> parents(fine.mesh.positions.size());
  for (std::size_t v = 0; v < parents.size(); ++v) {
    const geom::ClosestPoint hit = tree.closest_point(fine.mesh.positions[v]);
    const geom::Triangle& t = coarse.mesh.triangles[hit.triangle];
    const geom::Vec3& a = coarse.mesh.positions[t[0]];
    const geom::Vec3& b = coarse.mesh.positions[t[1]];
    const geom::Vec3& c = coarse.mesh.positions[t[2]];
    const geom::Vec3 normal = (b - a).cross(c - a);
    const double area = normal.squaredNorm();
    const double wa = (c - b).cross(hit.point - b).dot(normal) / area;
    const double wb = (a - c).cross(hit.point - c).dot(normal) / area;
    parents[v].vertices = {t[0], t[1], t[2]};
    parents[v].weights = {wa, wb, 1.0 - wa - wb};
  }
  return parents;
}

/// The lat-long field [-y, x, 0] projected on the tangent planes.
std::vector<geom::Vec3> lat_long_directions(const Level& level) {
  std::vector<geom::Vec3> field;
  for (const geom::Vec3& x : level.mesh.positions)
    field.emplace_back(-x.y(), x.x(), 0.0);
  return projected_directions(level.normals, field, nullptr);
}

/// Angle in degrees between two unit tangents at a vertex, modulo the symmetry (in [0, 180/n]).
double symmetric_gap_degrees(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& n,
                             int symmetry) {
  return std::abs(symmetric_residue(signed_angle(a, b, n), symmetry)) / kDegree;
}

/// argmin of E_p over a 0.01 degree scan of [0, 360/n).
double scanned_minimiser(std::span<const double> angles, int symmetry) {
  double best = 0.0;
  double best_energy = rotation_energy(angles, symmetry, 0.0);
  const int steps = 36000 / symmetry;
  for (int i = 1; i < steps; ++i) {
    const double theta = i * 0.01 * kDegree;
    const double energy = rotation_energy(angles, symmetry, theta);
    if (energy < best_energy) {
      best = theta;
      best_energy = energy;
    }
  }
  return best;
}

TEST(OrientationField, RandomDirectionsAreUnitTangentsKeyedByLevel) {
  const Level sphere(geom::icosphere(2));
  const auto level0 = random_directions(sphere.normals, 11, 0);
  const auto again = random_directions(sphere.normals, 11, 0);
  const auto level1 = random_directions(sphere.normals, 11, 1);
  ASSERT_EQ(level0.size(), sphere.normals.size());
  int differing = 0;
  for (std::size_t v = 0; v < level0.size(); ++v) {
    EXPECT_NEAR(level0[v].norm(), 1.0, 1e-12);
    EXPECT_NEAR(level0[v].dot(sphere.normals[v]), 0.0, 1e-12);
    EXPECT_EQ(level0[v], again[v]);
    differing += level0[v] != level1[v];
  }
  EXPECT_EQ(differing, int(level0.size()));
}

TEST(OrientationField, ProjectionCountsFieldsAlongTheNormal) {
  const std::vector<geom::Vec3> normals{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<geom::Vec3> field{{0, 0, 2}, {5, 3, 0}, {0, 0, 0}};
  std::int64_t degenerate = -1;
  const auto directions = projected_directions(normals, field, &degenerate);
  EXPECT_EQ(degenerate, 2);
  EXPECT_EQ(directions[0], tangent_basis(normals[0])[0]);
  EXPECT_NEAR((directions[1] - geom::Vec3(0, 1, 0)).norm(), 0.0, 1e-15);
  EXPECT_EQ(directions[2], tangent_basis(normals[2])[0]);
  const std::vector<geom::Vec3> bad{{0, 0, 2}, {NAN, 0, 0}, {0, 0, 0}};
  EXPECT_THROW(projected_directions(normals, bad, nullptr), InputError);
}

TEST(OrientationField, TransportIsAntisymmetric) {
  const CounterRng rng(3, 1);
  for (std::uint64_t i = 0; i < 200; ++i) {
    const geom::Vec3 n_p =
        geom::Vec3(rng.normal(i, 0, 0), rng.normal(i, 0, 1), rng.normal(i, 0, 2)).normalized();
    const geom::Vec3 n_q =
        (n_p + 0.5 * geom::Vec3(rng.normal(i, 1, 0), rng.normal(i, 1, 1), rng.normal(i, 1, 2)))
            .normalized();
    const geom::Vec3 s_p = direction_at_angle(n_p, rng.uniform(0.0, 7.0, i, 2));
    const geom::Vec3 s_q = direction_at_angle(n_q, rng.uniform(0.0, 7.0, i, 3));
    const auto pq = relative_angle(s_p, n_p, s_q, n_q);
    const auto qp = relative_angle(s_q, n_q, s_p, n_p);
    ASSERT_TRUE(pq && qp);
    EXPECT_NEAR(symmetric_residue(*pq + *qp, 1), 0.0, 1e-12);
  }
  EXPECT_FALSE(transport(geom::Vec3(1, 0, 0), geom::Vec3(0, 0, 1), geom::Vec3(0, 0, -1)));
}

TEST(OrientationRelaxation, MinimiserMatchesAFineScan) {
  const CounterRng rng(5, 2);
  for (const int symmetry : {1, 2, 4, 6}) {
    for (std::uint64_t trial = 0; trial < 40; ++trial) {
      const auto count = 1 + int(trial % 12);
      std::vector<double> angles;
      for (int k = 0; k < count; ++k)
        angles.push_back(rng.uniform(-10.0, 10.0, trial, symmetry, k));
      const double exact = minimising_rotation(angles, symmetry);
      const double scanned = scanned_minimiser(angles, symmetry);
      EXPECT_LE(rotation_energy(angles, symmetry, exact),
                rotation_energy(angles, symmetry, scanned) + 1e-12);
      EXPECT_LE(std::abs(symmetric_residue(exact - scanned, symmetry)), 0.01 * kDegree)
          << "n = " << symmetry << ", trial " << trial;
    }
  }
}

TEST(OrientationRelaxation, FirstUpdateMatchesAFineScan) {
  // Vertex 0 is always in the first colour class, so one sweep updates it from the initial
  // directions of its 1-ring and parent face.
  const Level coarse(geom::noisy(geom::icosphere(1), 0.05, 3));
  const Level fine(geom::noisy(geom::icosphere(2), 0.05, 4));
  const auto parents = closest_parent_faces(fine, coarse);
  const auto coarse_directions = random_directions(coarse.normals, 9, 1);
  const auto coarser = coarser_orientation(parents, coarse_directions, coarse.normals);
  for (const int symmetry : {1, 2, 4}) {
    for (const CoarserOrientation* parent_level : {&coarser, (const CoarserOrientation*)nullptr}) {
      const auto start = random_directions(fine.normals, 9, 2);
      std::vector<double> angles;
      for (const std::int32_t q : fine.topology.vertex_neighbors().row(0))
        angles.push_back(*relative_angle(start[0], fine.normals[0], start[q], fine.normals[q]));
      if (parent_level != nullptr)
        for (const std::int32_t u : parents[0].vertices)
          angles.push_back(
              *relative_angle(start[0], fine.normals[0], coarse_directions[u], coarse.normals[u]));
      const double theta = scanned_minimiser(angles, symmetry);
      auto directions = start;
      const par::Comm self = test::self_comm();
      relax_directions(self, equal_runs(self, fine.topology.num_vertices()), own_rings(self, fine),
                       fine.normals, parent_level, symmetry, 1, directions);
      const double moved = signed_angle(start[0], directions[0], fine.normals[0]);
      EXPECT_LE(std::abs(symmetric_residue(moved - theta, symmetry)), 0.01 * kDegree)
          << "n = " << symmetry;
    }
  }
}

TEST(OrientationRelaxation, EnergyNeverRises) {
  const Level coarse(geom::icosphere(2));
  const Level fine(geom::noisy(geom::icosphere(3), 0.02, 5));
  const auto parents = closest_parent_faces(fine, coarse);
  const auto coarse_directions = lat_long_directions(coarse);
  const par::Comm world = par::world();
  const auto run_parents = own_run(world, parents);
  const auto coarser = coarser_orientation(run_parents, coarse_directions, coarse.normals);
  for (const int symmetry : {1, 2, 4})
    for (const CoarserOrientation* parent_level : {&coarser, (const CoarserOrientation*)nullptr}) {
      auto directions = own_run(world, random_directions(fine.normals, 21, 1));
      const RelaxationReport report = relax_directions(
          world, equal_runs(world, fine.topology.num_vertices()), own_rings(world, fine),
          own_run(world, fine.normals), parent_level, symmetry, 30, directions);
      ASSERT_EQ(report.energy.size(), 31u);
      EXPECT_GE(report.colour_classes, 4);
      EXPECT_LT(report.energy.back(), 0.2 * report.energy.front());
      for (std::size_t k = 1; k < report.energy.size(); ++k)
        EXPECT_LE(report.energy[k], report.energy[k - 1] + 1e-12 * report.energy.front())
            << "n = " << symmetry << ", sweep " << k;
    }
}

/// A planar grid of side x side vertices in z = 0, normals +z.
Level planar_grid(int side) {
  geom::TriangleMesh mesh;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i)
      mesh.positions.emplace_back(i, j, 0.0);
  for (int j = 0; j + 1 < side; ++j)
    for (int i = 0; i + 1 < side; ++i) {
      const std::int32_t v = j * side + i;
      mesh.triangles.push_back({v, v + 1, v + side + 1});
      mesh.triangles.push_back({v, v + side + 1, v + side});
    }
  return Level(std::move(mesh));
}

TEST(OrientationRelaxation, QuarterTurnsAreFixedForFourWayOnly) {
  const Level grid = planar_grid(12);
  const CounterRng rng(8, 3);
  std::vector<geom::Vec3> start;
  for (std::int32_t v = 0; v < grid.topology.num_vertices(); ++v)
    start.push_back(direction_at_angle(grid.normals[v], std::floor(rng.uniform(0.0, 4.0, v, 0)) *
                                                            0.5 * std::numbers::pi));
  const par::Comm world = par::world();
  const auto runs = equal_runs(world, grid.topology.num_vertices());
  auto four_way = own_run(world, start);
  const auto fixed = relax_directions(world, runs, own_rings(world, grid),
                                      own_run(world, grid.normals), nullptr, 4, 5, four_way);
  EXPECT_LT(fixed.energy.front(), 1e-20);
  four_way = whole_level(world, four_way, grid.topology.num_vertices());
  auto two_way = own_run(world, start);
  const auto moved = relax_directions(world, runs, own_rings(world, grid),
                                      own_run(world, grid.normals), nullptr, 2, 5, two_way);
  EXPECT_LT(moved.energy.back(), 0.5 * moved.energy.front());
  two_way = whole_level(world, two_way, grid.topology.num_vertices());
  double largest_four = 0.0;
  double largest_two = 0.0;
  for (std::size_t v = 0; v < start.size(); ++v) {
    largest_four =
        std::max(largest_four, symmetric_gap_degrees(start[v], four_way[v], grid.normals[v], 1));
    largest_two =
        std::max(largest_two, symmetric_gap_degrees(start[v], two_way[v], grid.normals[v], 1));
  }
  EXPECT_LT(largest_four, 1e-9);
  EXPECT_GT(largest_two, 10.0);
}

/// Fraction of edges whose symmetric residue is below `degrees`.
double smooth_edge_fraction(const Level& level, const std::vector<geom::Vec3>& directions,
                            int symmetry, double degrees) {
  int smooth = 0;
  for (const geom::Edge& e : level.topology.edges()) {
    const auto phi = relative_angle(directions[e[0]], level.normals[e[0]], directions[e[1]],
                                    level.normals[e[1]]);
    smooth += phi && std::abs(symmetric_residue(*phi, symmetry)) < degrees * kDegree;
  }
  return double(smooth) / level.topology.num_edges();
}

TEST(OrientationRelaxation, RelaxedSphereIsSmoothAlmostEverywhere) {
  // As the pipeline runs it (Section 3.1): the coarsest level starts random, each finer level
  // starts from its parent faces; 30 sweeps of 2-way relaxation per level; four levels of 162 to
  // 10,242 vertices (the finest gives 96% smooth edges).
  const par::Comm world = par::world();
  std::unique_ptr<Level> coarse;
  std::vector<geom::Vec3> coarse_directions; // relaxed, on the whole of `coarse`
  for (int refinement = 2; refinement <= 5; ++refinement) {
    auto level = std::make_unique<Level>(geom::icosphere(refinement));
    const std::int64_t count = level->topology.num_vertices();
    auto directions = own_run(world, random_directions(level->normals, 2, 5 - refinement));
    std::vector<ParentFace> parents;
    std::optional<CoarserOrientation> coarser;
    if (coarse == nullptr) {
      EXPECT_LT(smooth_edge_fraction(*level, whole_level(world, directions, count), 2, 5.0), 0.1);
    } else {
      parents = own_run(world, closest_parent_faces(*level, *coarse));
      coarser = coarser_orientation(parents, coarse_directions, coarse->normals);
      directions = inherited_directions(own_run(world, level->normals), *coarser, 2, directions);
    }
    relax_directions(world, equal_runs(world, count), own_rings(world, *level),
                     own_run(world, level->normals), coarser ? &*coarser : nullptr, 2, 30,
                     directions);
    coarse = std::move(level);
    coarse_directions = whole_level(world, directions, count);
  }
  EXPECT_GE(smooth_edge_fraction(*coarse, coarse_directions, 2, 5.0), 0.9);
}

/// The raw bytes of a vector of directions.
std::vector<unsigned char> bytes_of(const std::vector<geom::Vec3>& directions) {
  std::vector<unsigned char> bytes(directions.size() * sizeof(geom::Vec3));
  std::memcpy(bytes.data(), directions.data(), bytes.size());
  return bytes;
}

TEST(OrientationRelaxation, SameBitsOnAnyRankAndThreadCount) {
  const Level coarse(geom::icosphere(2));
  const Level fine(geom::noisy(geom::icosphere(3), 0.02, 6));
  const auto parents = closest_parent_faces(fine, coarse);
  const auto coarse_directions = random_directions(coarse.normals, 4, 2);
  const auto coarser = coarser_orientation(parents, coarse_directions, coarse.normals);
  const auto start =
      inherited_directions(fine.normals, coarser, 2, random_directions(fine.normals, 4, 3));
  const par::Comm world = par::world();
  const par::Comm self = test::self_comm();
  const std::int64_t count = fine.topology.num_vertices();
  auto distributed = own_run(world, start);
  const auto run_parents = own_run(world, parents);
  const auto coarser_run = coarser_orientation(run_parents, coarse_directions, coarse.normals);
  const auto distributed_report =
      relax_directions(world, equal_runs(world, count), own_rings(world, fine),
                       own_run(world, fine.normals), &coarser_run, 2, 10, distributed);
  distributed = whole_level(world, distributed, count);
  auto serial = start;
  const auto serial_report = relax_directions(self, equal_runs(self, count), own_rings(self, fine),
                                              fine.normals, &coarser, 2, 10, serial);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(3);
  auto threaded = start;
  relax_directions(self, equal_runs(self, count), own_rings(self, fine), fine.normals, &coarser, 2,
                   10, threaded);
  omp_set_num_threads(threads);
  EXPECT_EQ(bytes_of(threaded), bytes_of(serial));
  EXPECT_EQ(bytes_of(distributed), bytes_of(serial));
  EXPECT_EQ(distributed_report.energy, serial_report.energy);
  EXPECT_EQ(distributed_report.colour_classes, serial_report.colour_classes);
  EXPECT_NE(bytes_of(serial), bytes_of(start));
}

/// The serial faces of the run of each rank, from find_parent_faces on the coarse level split
/// over the ranks with a window of `reach`, byte for byte.
void expect_serial_faces(std::span<const geom::Vec3> points, std::span<const geom::Vec3> normals,
                         const geom::TriangleMesh& coarse, double reach) {
  const auto serial = find_parent_faces(points, normals, coarse, geom::AabbTree(coarse));
  const par::Comm world = par::world();
  const auto runs = equal_runs(world, std::int64_t(points.size()));
  const auto first = std::size_t(runs[world.rank]);
  const auto count = std::size_t(runs[world.rank + 1]) - first;
  const auto distributed =
      find_parent_faces(world, points.subspan(first, count), normals.subspan(first, count),
                        geom::DistributedTriangles::from_replicated(world, coarse), reach);
  ASSERT_EQ(distributed.size(), count);
  for (std::size_t i = 0; i < count; ++i)
    EXPECT_EQ(std::memcmp(&distributed[i], &serial[first + i], sizeof(ParentFace)), 0)
        << "point " << first + i << " with reach " << reach;
}

void expect_serial_faces(const Level& fine, const geom::TriangleMesh& coarse, double reach) {
  expect_serial_faces(fine.mesh.positions, fine.normals, coarse, reach);
}

TEST(ParentFaces, RunsSearchedOnWindowsGiveTheSerialFaces) {
  const Level coarse(geom::icosphere(2));
  const Level fine(geom::noisy(geom::icosphere(3), 0.02, 6));
  const double spacing = geom::mean_edge_length(coarse.mesh);
  // The usual window; one too narrow to vouch for any hit (every point asks every rank); one
  // holding the whole level.
  for (const double reach : {parent_window_reach(spacing), 1e-6, 10.0})
    expect_serial_faces(fine, coarse.mesh, reach);
  const auto serial = find_parent_faces(fine.mesh.positions, fine.normals, coarse.mesh,
                                        geom::AabbTree(coarse.mesh));
  EXPECT_TRUE(std::all_of(serial.begin(), serial.end(), [](const auto& p) { return p.found(); }));
}

TEST(ParentFaces, MissesAndFarHitsOnAnOpenLevelGiveTheSerialFaces) {
  // A cap of the sphere: lines from the equator miss it, lines from the south cross it far
  // beyond any window, lines from the north cross it near their points.
  const Level fine(geom::noisy(geom::icosphere(3), 0.02, 6));
  geom::TriangleMesh cap = geom::icosphere(2);
  std::erase_if(cap.triangles, [&](const geom::Triangle& t) {
    return (cap.positions[t[0]] + cap.positions[t[1]] + cap.positions[t[2]]).z() < 1.5;
  });
  const auto serial =
      find_parent_faces(fine.mesh.positions, fine.normals, cap, geom::AabbTree(cap));
  std::int64_t misses = 0, far = 0;
  for (std::size_t v = 0; v < serial.size(); ++v) {
    misses += !serial[v].found();
    far += serial[v].found() && fine.mesh.positions[v].z() < 0;
  }
  ASSERT_GT(misses, 0);
  ASSERT_GT(far, 0);
  expect_serial_faces(fine, cap, parent_window_reach(geom::mean_edge_length(cap)));
}

TEST(ParentFaces, AFarCrossingInTheWindowIsNotTakenForTheNearest) {
  // Two small parallel triangles over point a, at heights 0.5 and 2. The window of reach 0.05
  // around a and b (on the upper triangle) holds only the upper one: a's crossing there is
  // farther than the reach, so the lower triangle, outside the window, must be asked for.
  geom::TriangleMesh levels;
  for (const double z : {0.5, 2.0}) {
    const auto base = std::int32_t(levels.positions.size());
    levels.positions.insert(
        levels.positions.end(),
        {geom::Vec3(-0.1, -0.1, z), geom::Vec3(0.1, -0.1, z), geom::Vec3(0, 0.1, z)});
    levels.triangles.push_back({base, base + 1, base + 2});
  }
  const std::vector<geom::Vec3> points{{0, 0, 0}, {0.05, 0, 2}};
  const std::vector<geom::Vec3> normals{{0, 0, 1}, {1, 0, 0}};
  const auto serial = find_parent_faces(points, normals, levels, geom::AabbTree(levels));
  ASSERT_EQ(serial[0].triangle, 0);
  expect_serial_faces(points, normals, levels, 0.05);
}

TEST(OrientationField, InheritedDirectionsReproduceASmoothParentField) {
  const Level coarse(geom::icosphere(3));
  const Level fine(geom::icosphere(4));
  const auto parents = closest_parent_faces(fine, coarse);
  const auto coarse_directions = lat_long_directions(coarse);
  const auto expected = lat_long_directions(fine);
  const auto fallback = random_directions(fine.normals, 1, 4);
  for (const int symmetry : {1, 2, 4}) {
    const auto inherited = inherited_directions(
        fine.normals, coarser_orientation(parents, coarse_directions, coarse.normals), symmetry,
        fallback);
    double largest = 0.0;
    for (std::size_t v = 0; v < inherited.size(); ++v) {
      EXPECT_NEAR(inherited[v].norm(), 1.0, 1e-12);
      EXPECT_NEAR(inherited[v].dot(fine.normals[v]), 0.0, 1e-12);
      if (std::abs(fine.mesh.positions[v].z()) < 0.9)
        largest = std::max(
            largest, symmetric_gap_degrees(expected[v], inherited[v], fine.normals[v], symmetry));
    }
    EXPECT_LT(largest, 1.0) << "n = " << symmetry;
  }
}

TEST(OrientationField, CornersFetchedFromTheirOwnersAreTheSerialOnes) {
  const Level coarse(geom::noisy(geom::icosphere(2), 0.05, 7));
  const Level fine(geom::noisy(geom::icosphere(3), 0.05, 8));
  const auto parents = own_run(par::world(), closest_parent_faces(fine, coarse));
  const auto coarse_directions = random_directions(coarse.normals, 3, 1);
  const auto serial = coarser_orientation(parents, coarse_directions, coarse.normals);
  const par::Comm world = par::world();
  const auto fetched =
      coarser_orientation(world, parents, equal_runs(world, coarse.topology.num_vertices()),
                          own_run(world, coarse_directions), own_run(world, coarse.normals));
  ASSERT_EQ(fetched.directions.size(), parents.size());
  ASSERT_EQ(fetched.normals.size(), parents.size());
  for (std::size_t v = 0; v < parents.size(); ++v) {
    ASSERT_TRUE(parents[v].found());
    EXPECT_EQ(std::memcmp(&fetched.directions[v], &serial.directions[v], 3 * sizeof(geom::Vec3)),
              0);
    EXPECT_EQ(std::memcmp(&fetched.normals[v], &serial.normals[v], 3 * sizeof(geom::Vec3)), 0);
    EXPECT_EQ(serial.directions[v][1], coarse_directions[std::size_t(parents[v].vertices[1])]);
  }
}

} // namespace
} // namespace texsim::pipelines::surface_synthesis
