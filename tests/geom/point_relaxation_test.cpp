// Turk's point relaxation: the repulsion law and one sweep on hand-checked configurations, the
// point halo exchange against a brute-force selection, and the distributed relaxation: random
// points (nearest-neighbour distances with a coefficient of variation above 0.3) become evenly
// spaced (below 0.1) on a sphere and on a real mesh, stay on their triangles, and give the same
// bytes as a run on one process and with another thread count.
#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/point_relaxation.hpp"
#include "geom/random_surface_points.hpp"
#include "par/morton_partition.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>

namespace texsim::geom {
namespace {

par::Comm self() {
  par::Comm comm;
  comm.raw = MPI_COMM_SELF;
  return comm;
}

// [0, n]^2 in the plane z = 0, each unit square split into two triangles.
TriangleMesh flat_grid(int n) {
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.positions.emplace_back(i, j, 0.0);
  const auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

std::int32_t find_triangle(const TriangleMesh& mesh, const Vec3& p) {
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    const double area = (b - a).cross(c - a).z();
    const double l1 = (p - a).cross(c - a).z() / area, l2 = (b - a).cross(p - a).z() / area;
    if (l1 >= 0 && l2 >= 0 && l1 + l2 <= 1)
      return t;
  }
  return -1;
}

bool same_bits(const Vec3& a, const Vec3& b) {
  return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0;
}

TEST(Repulsion, FallsLinearlyToZeroAtTheRadius) {
  const Vec3 p(1, 2, 3);
  const Vec3 direction = Vec3(1, -2, 2) / 3.0;
  for (const double d : {0.1, 0.5, 0.99}) {
    const Vec3 f = repulsion(p, 0, p - d * direction, 1, 1.0);
    EXPECT_LT((f - (1.0 - d) * direction).norm(), 1e-14) << d;
  }
  EXPECT_EQ(repulsion(p, 0, p - Vec3(0, 0, 1), 1, 1.0), Vec3::Zero());
  EXPECT_EQ(repulsion(p, 0, p - 2.0 * direction, 1, 1.0), Vec3::Zero());
  // Coincident points are pushed apart with the full strength, in opposite senses.
  const Vec3 f01 = repulsion(p, 0, p, 1, 2.0), f10 = repulsion(p, 1, p, 0, 2.0);
  EXPECT_NEAR(f01.norm(), 2.0, 1e-14);
  EXPECT_EQ(f01, -f10);
}

TEST(RelaxationSweep, PushesNeighboursApartAndLeavesLonelyPointsAlone) {
  const auto mesh = flat_grid(10);
  const MeshTopology topology(mesh);
  const SurfaceWalker walker(mesh, topology);
  const RelaxationSettings settings; // radius_factor 2: about 4 pi points within r
  const double radius = 1.0;
  const Vec3 a(5.0, 5.0, 0), b(5.4, 5.0, 0), lonely(8.0, 2.0, 0);
  const std::vector<std::int64_t> ids{3, 8, 20};
  const std::vector<SurfacePoint> points{{a, find_triangle(mesh, a)},
                                         {b, find_triangle(mesh, b)},
                                         {lonely, find_triangle(mesh, lonely)}};
  double move_sum = 0;
  const auto moved = relaxation_sweep(walker, ids, points, {}, radius, settings, &move_sum);
  // Force (r - d) = 0.6 along the line, move = step * force / (pi radius_factor^2).
  const double shift = settings.step * 0.6 / (std::numbers::pi * 4.0);
  EXPECT_LT((moved[0].position - Vec3(5.0 - shift, 5.0, 0)).norm(), 1e-14);
  EXPECT_LT((moved[1].position - Vec3(5.4 + shift, 5.0, 0)).norm(), 1e-14);
  EXPECT_TRUE(same_bits(moved[2].position, lonely));
  EXPECT_NEAR(move_sum, 2 * shift, 1e-14);
  EXPECT_LT((relaxation_move(Vec3(0.6, 0, 0), radius, settings) - Vec3(shift, 0, 0)).norm(), 1e-16);

  // The same neighbour as a halo point gives the same bytes.
  const std::vector<HaloPoint> halo{{8, b, 1, 0}};
  const auto alone = relaxation_sweep(walker, std::vector<std::int64_t>{3},
                                      std::vector<SurfacePoint>{points[0]}, halo, radius, settings);
  EXPECT_TRUE(same_bits(alone[0].position, moved[0].position));

  // The move is capped at step * r.
  const Vec3 capped = relaxation_move(Vec3(1e3, 0, 0), radius, settings);
  EXPECT_NEAR(capped.norm(), settings.step * radius, 1e-12);
}

// Everybody's points (allgathered) that lie in one of `boxes` and belong to another rank, sorted
// by id: what exchange_point_halo must return.
std::vector<HaloPoint> brute_force_halo(const par::Comm& comm, const std::vector<std::int64_t>& ids,
                                        const std::vector<Vec3>& positions,
                                        const std::vector<Box3>& boxes) {
  int n = static_cast<int>(ids.size());
  std::vector<int> counts(comm.size), offsets(comm.size);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm.raw);
  int total = 0;
  for (int r = 0; r < comm.size; ++r) {
    offsets[r] = total;
    total += counts[r];
  }
  std::vector<std::int64_t> all_ids(total);
  MPI_Allgatherv(ids.data(), n, MPI_INT64_T, all_ids.data(), counts.data(), offsets.data(),
                 MPI_INT64_T, comm.raw);
  std::vector<double> xyz(3 * ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i)
    for (int k = 0; k < 3; ++k)
      xyz[3 * i + k] = positions[i][k];
  std::vector<int> counts3(comm.size), offsets3(comm.size);
  for (int r = 0; r < comm.size; ++r) {
    counts3[r] = 3 * counts[r];
    offsets3[r] = 3 * offsets[r];
  }
  std::vector<double> all_xyz(3 * std::size_t(total));
  MPI_Allgatherv(xyz.data(), 3 * n, MPI_DOUBLE, all_xyz.data(), counts3.data(), offsets3.data(),
                 MPI_DOUBLE, comm.raw);
  std::vector<HaloPoint> expected;
  for (int r = 0; r < comm.size; ++r) {
    if (r == comm.rank)
      continue;
    for (int i = 0; i < counts[r]; ++i) {
      const int g = offsets[r] + i;
      const Vec3 p(all_xyz[3 * g], all_xyz[3 * g + 1], all_xyz[3 * g + 2]);
      if (std::any_of(boxes.begin(), boxes.end(), [&](const Box3& b) { return b.contains(p); }))
        expected.push_back({all_ids[g], p, r, i});
    }
  }
  std::sort(expected.begin(), expected.end(),
            [](const HaloPoint& x, const HaloPoint& y) { return x.id < y.id; });
  return expected;
}

void expect_same_halo(const std::vector<HaloPoint>& halo, const std::vector<HaloPoint>& expected) {
  ASSERT_EQ(halo.size(), expected.size());
  for (std::size_t k = 0; k < halo.size(); ++k) {
    EXPECT_EQ(halo[k].id, expected[k].id);
    EXPECT_TRUE(same_bits(halo[k].position, expected[k].position));
    EXPECT_EQ(halo[k].owner, expected[k].owner);
    EXPECT_EQ(halo[k].owner_index, expected[k].owner_index);
  }
}

TEST(PointHalo, ReceivesExactlyTheOtherRanksPointsInsideTheBox) {
  const auto comm = par::world();
  // Each rank owns points along its own unit of the x axis, in a shuffled id order, plus a few
  // scattered in y; the last rank owns none when there are several.
  std::vector<std::int64_t> ids;
  std::vector<Vec3> positions;
  const bool empty = comm.size > 1 && comm.rank == comm.size - 1;
  if (!empty)
    for (int i = 0; i < 60; ++i) {
      ids.push_back(std::int64_t(comm.rank) * 1000 + (i * 37) % 60);
      positions.emplace_back(comm.rank + (i + 0.5) / 60.0, i % 7 == 0 ? 0.5 : 0.0, 0.0);
    }
  const Box3 needed = Box3::around(positions).expanded(0.1);
  EXPECT_EQ(needed.empty(), empty);
  const auto halo = exchange_point_halo(comm, ids, positions, needed);
  expect_same_halo(halo, brute_force_halo(comm, ids, positions, {needed}));
  // Neighbouring ranks (both with points) share a band of 0.1: 6 points each way.
  if (comm.size >= 3 && comm.rank == 0) {
    EXPECT_EQ(halo.size(), 6u);
  }
}

TEST(PointHalo, UnionOfCoveringBoxesOnASurface) {
  // Ranks own Morton parts of random torus points: a part's bounding box overlaps much of the
  // others', its covering boxes do not.
  const auto comm = par::world();
  const auto mesh = torus(2.0, 0.6, 40, 16);
  const std::int64_t count = 3000;
  const auto all = random_surface_points(mesh, 0, count, 8);
  std::vector<std::array<double, 3>> xyz;
  for (const auto& p : all)
    xyz.push_back({p.position.x(), p.position.y(), p.position.z()});
  const auto part = par::morton_partition(xyz, comm.size);
  std::vector<std::int64_t> ids;
  std::vector<Vec3> positions;
  for (std::int64_t id = 0; id < count; ++id)
    if (part[id] == comm.rank) {
      ids.push_back(id);
      positions.push_back(all[id].position);
    }
  const double reach = 0.15;
  const auto boxes = covering_boxes(positions, 0.4, reach);
  // Every point within reach of an owned point is covered.
  for (const auto& p : all) {
    const bool near = std::any_of(positions.begin(), positions.end(),
                                  [&](const Vec3& q) { return (q - p.position).norm() <= reach; });
    if (near) {
      EXPECT_TRUE(std::any_of(boxes.begin(), boxes.end(),
                              [&](const Box3& b) { return b.contains(p.position); }));
    }
  }
  const auto halo = exchange_point_halo(comm, ids, positions, std::span<const Box3>(boxes));
  expect_same_halo(halo, brute_force_halo(comm, ids, positions, boxes));
  if (comm.size > 1) {
    const auto loose =
        exchange_point_halo(comm, ids, positions, Box3::around(positions).expanded(reach));
    EXPECT_LT(halo.size(), loose.size());
  }
}

TEST(Box3, AroundExpandedContains) {
  const std::vector<Vec3> points{Vec3(0, 1, 2), Vec3(-1, 3, 0)};
  const Box3 box = Box3::around(points);
  EXPECT_EQ(box.lo, Vec3(-1, 1, 0));
  EXPECT_EQ(box.hi, Vec3(0, 3, 2));
  EXPECT_TRUE(box.contains(Vec3(0, 3, 2)));
  EXPECT_FALSE(box.contains(Vec3(0.1, 3, 2)));
  EXPECT_TRUE(box.expanded(0.2).contains(Vec3(0.1, 3, 2)));
  const Box3 none = Box3::around({});
  EXPECT_TRUE(none.empty());
  EXPECT_FALSE(none.expanded(1e6).contains(Vec3::Zero()));
}

TEST(NearestNeighborSpacing, ExactOnALatticeAndAgreesWithBruteForce) {
  std::vector<Vec3> lattice;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 20; ++j)
      lattice.emplace_back(0.25 * i, 0.25 * j, 3.0);
  const auto spacing = nearest_neighbor_spacing(lattice);
  EXPECT_NEAR(spacing.mean, 0.25, 1e-12);
  EXPECT_NEAR(spacing.cv, 0.0, 1e-12);

  const auto mesh = torus(2.0, 0.5, 30, 12);
  std::vector<Vec3> points;
  for (const auto& p : random_surface_points(mesh, 0, 1500, 4))
    points.push_back(p.position);
  points.emplace_back(40.0, 0.0, 0.0); // far from everything: the search must widen
  std::vector<double> nearest(points.size(), 1e300);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = 0; j < points.size(); ++j)
      if (i != j)
        nearest[i] = std::min(nearest[i], (points[i] - points[j]).norm());
  double mean = 0;
  for (double d : nearest)
    mean += d / double(points.size());
  double variance = 0;
  for (double d : nearest)
    variance += (d - mean) * (d - mean) / double(points.size());
  const auto measured = nearest_neighbor_spacing(points);
  EXPECT_NEAR(measured.mean, mean, 1e-12);
  EXPECT_NEAR(measured.cv, std::sqrt(variance) / mean, 1e-12);
  EXPECT_NEAR(measured.max, *std::max_element(nearest.begin(), nearest.end()), 1e-12);
}

// All ranks' points, indexed by id; checks that every id is owned exactly once.
std::vector<SurfacePoint> gather_by_id(const par::Comm& comm, const DistributedSurfacePoints& mine,
                                       std::int64_t count) {
  EXPECT_TRUE(std::is_sorted(mine.ids.begin(), mine.ids.end()));
  EXPECT_EQ(mine.ids.size(), mine.points.size());
  int n = static_cast<int>(mine.ids.size());
  std::vector<int> counts(comm.size), offsets(comm.size);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm.raw);
  int total = 0;
  for (int r = 0; r < comm.size; ++r) {
    offsets[r] = total;
    total += counts[r];
  }
  EXPECT_EQ(total, count);
  std::vector<std::int64_t> ids(total);
  MPI_Allgatherv(mine.ids.data(), n, MPI_INT64_T, ids.data(), counts.data(), offsets.data(),
                 MPI_INT64_T, comm.raw);
  std::vector<double> xyzt(4 * mine.ids.size());
  for (std::size_t i = 0; i < mine.ids.size(); ++i) {
    for (int k = 0; k < 3; ++k)
      xyzt[4 * i + k] = mine.points[i].position[k];
    xyzt[4 * i + 3] = mine.points[i].triangle;
  }
  for (int r = 0; r < comm.size; ++r) {
    counts[r] *= 4;
    offsets[r] *= 4;
  }
  std::vector<double> all(4 * std::size_t(total));
  MPI_Allgatherv(xyzt.data(), 4 * n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                 MPI_DOUBLE, comm.raw);
  std::vector<SurfacePoint> by_id(count);
  std::vector<int> seen(count, 0);
  for (int g = 0; g < total; ++g) {
    const auto id = ids[g];
    EXPECT_TRUE(id >= 0 && id < count);
    if (id < 0 || id >= count)
      continue;
    ++seen[id];
    by_id[id] = {Vec3(all[4 * g], all[4 * g + 1], all[4 * g + 2]), std::int32_t(all[4 * g + 3])};
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), count) << "ids owned more or less than once";
  return by_id;
}

std::vector<Vec3> positions_of(const std::vector<SurfacePoint>& points) {
  std::vector<Vec3> positions;
  for (const auto& p : points)
    positions.push_back(p.position);
  return positions;
}

// The relaxation on `mesh`: evenness before and after, on-triangle, and bitwise agreement with a
// run on one process (with 1 and with 3 threads).
void check_relaxation(const TriangleMesh& mesh, std::int64_t count, std::uint64_t seed) {
  const auto comm = par::world();
  const RelaxationSettings settings;
  const auto initial =
      nearest_neighbor_spacing(positions_of(random_surface_points(mesh, 0, count, seed)));
  EXPECT_GT(initial.cv, 0.3);

  RelaxationReport report;
  // Split from rank 0, as turk_rd does: no other rank sees the whole mesh.
  const auto split = DistributedTriangles::from_root(comm, comm.is_root() ? mesh : TriangleMesh{});
  const auto mine = relaxed_surface_points(comm, split, count, seed, settings, &report);
  const auto relaxed = gather_by_id(comm, mine, count);
  const auto spacing = nearest_neighbor_spacing(positions_of(relaxed));
  EXPECT_LT(spacing.cv, 0.1) << "random: " << initial.cv;
  // Near-hexagonal: the mean nearest-neighbour distance approaches the lattice spacing
  // sqrt(2 A / (sqrt(3) n)), far above the random mean (half of sqrt(A / n)).
  const double area = total_area(mesh);
  EXPECT_GT(spacing.mean, 0.8 * std::sqrt(2.0 * area / (std::sqrt(3.0) * double(count))));
  EXPECT_DOUBLE_EQ(report.radius, settings.radius_factor * std::sqrt(area / double(count)));
  EXPECT_EQ(report.seconds_per_iteration.size(), std::size_t(settings.iterations));
  EXPECT_LT(report.mean_move_per_iteration.back(), report.mean_move_per_iteration.front());
  // The windows: fetched at the start and again only as points drift, and, once a rank's points
  // cover a region many moves wide (thousands of points per rank), never the whole mesh.
  EXPECT_GE(report.window_fetches, 1);
  EXPECT_LT(report.window_fetches, settings.iterations);
  if (comm.size > 1 && count >= 5000 * comm.size) {
    EXPECT_LT(report.window_triangles_max, 3 * mesh.num_triangles() / 4) << report.window_fetches;
  }

  // Every point lies on its triangle.
  int off = 0;
  for (const auto& p : relaxed) {
    const auto& tri = mesh.triangles.at(p.triangle);
    const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    Eigen::Matrix<double, 3, 2> edges;
    edges << b - a, c - a;
    const Eigen::Vector2d st = edges.colPivHouseholderQr().solve(p.position - a);
    const double plane = std::abs((b - a).cross(c - a).normalized().dot(p.position - a));
    off += plane > 1e-12 * (1.0 + a.norm()) || st.minCoeff() < -1e-12 || st.sum() > 1 + 1e-12;
  }
  EXPECT_EQ(off, 0);

  // The same bytes on one process, whatever the thread count.
  for (const int threads : {1, 3}) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    const auto serial = relaxed_surface_points(
        self(), DistributedTriangles::from_replicated(self(), mesh), count, seed, settings);
    omp_set_num_threads(before);
    ASSERT_EQ(serial.ids.size(), std::size_t(count));
    int differ = 0;
    for (std::int64_t id = 0; id < count; ++id)
      differ += !same_bits(serial.points[id].position, relaxed[id].position) ||
                serial.points[id].triangle != relaxed[id].triangle;
    EXPECT_EQ(differ, 0) << "with " << threads << " threads on one process";
  }
}

TEST(RelaxedSurfacePoints, EvenlySpacedOnASphere) {
  check_relaxation(icosphere(4), 3000, 17);
}

TEST(RelaxedSurfacePointsOnRealData, EvenlySpacedOnTheBunny) {
  const auto path = test::real_data("meshes/bunny00.off");
  if (path.empty())
    GTEST_SKIP() << test::missing_data_message("meshes/bunny00.off");
  check_relaxation(read_mesh(path), 20000, 3);
}

TEST(RelaxedSurfacePoints, RejectsBadSettings) {
  const auto mesh = DistributedTriangles::from_replicated(par::world(), icosphere(1));
  RelaxationSettings bad;
  bad.step = 0.0;
  EXPECT_THROW(relaxed_surface_points(par::world(), mesh, 10, 1, bad), Error);
  EXPECT_THROW(relaxed_surface_points(par::world(), mesh, 0, 1, {}), Error);
}

} // namespace
} // namespace texsim::geom
