// DistributedMesh keeps each rank's part only: every vertex and triangle is owned exactly once, no
// rank holds more than its part and the halo it reports, the halo is complete to three rings
// (curvature on the local part equals curvature on the whole surface at owned vertices), and
// update_halo brings the owners' values. Refined on the parts (Loop and sphere rounds), the
// surface is the serial refinement's, bit for bit. At 1, 2 and 3 ranks, on generated spheres and
// squares and on the raw scanned bunny (holes, boundary vertices).
#include "geom/crease_edges.hpp"
#include "geom/curvature_tensor.hpp"
#include "geom/distributed_measures.hpp"
#include "geom/distributed_mesh.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/patch_refinement.hpp"
#include "par/record_exchange.hpp"
#include "support/gather_by_id.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <span>

namespace texsim::geom {
namespace {

std::int64_t summed(std::int64_t value) {
  std::int64_t total = 0;
  MPI_Allreduce(&value, &total, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  return total;
}

/// Triangles as sorted input-id triples, sorted: compares triangle sets across numberings.
std::vector<std::array<std::int64_t, 3>>
sorted_triples(std::vector<std::array<std::int64_t, 3>> t) {
  for (auto& triple : t)
    std::sort(triple.begin(), triple.end());
  std::sort(t.begin(), t.end());
  return t;
}

std::vector<RefinementStep> rounds(int count, RefinementStep step = {}) {
  return std::vector<RefinementStep>(std::size_t(count), step);
}

/// `coarse` distributed and refined by `refinement` on the ranks' parts with `creases` kept
/// sharp, against the whole mesh refined serially.
void check_ownership(const TriangleMesh& coarse, PartitionMethod method,
                     const std::vector<RefinementStep>& refinement = {},
                     std::span<const char> creases = {}) {
  const par::Comm comm = par::world();
  const DistributedMesh mesh(comm, coarse, method, refinement, creases);
  std::vector<char> fine_creases;
  const TriangleMesh input = refine(coarse, refinement, creases, &fine_creases);
  const std::int64_t n = input.num_vertices();
  ASSERT_EQ(mesh.global_count(), n);
  ASSERT_EQ(mesh.global_triangle_count(), input.num_triangles());

  // Every vertex owned once: the owned input ids of all ranks are a permutation of 0..n-1.
  EXPECT_EQ(summed(mesh.owned_count()), n);
  std::vector<double> ones(std::size_t(mesh.owned_count()), 1.0);
  const auto owned_times = test::gather_by_id(comm, mesh.owned_input_ids(), ones);
  EXPECT_EQ(std::count(owned_times.begin(), owned_times.end(), 1.0), n);

  // Every triangle owned once: the owned triangles of all ranks are the input's triangles.
  std::vector<std::array<std::int64_t, 3>> mine;
  for (const std::int32_t t : mesh.owned_triangles()) {
    const auto& tri = mesh.mesh().triangles[t];
    mine.push_back({mesh.input_id()[tri[0]], mesh.input_id()[tri[1]], mesh.input_id()[tri[2]]});
  }
  const auto all = par::allgather_records(comm, mine);
  std::vector<std::array<std::int64_t, 3>> expected;
  for (const auto& tri : input.triangles)
    expected.push_back({tri[0], tri[1], tri[2]});
  EXPECT_EQ(sorted_triples(all), sorted_triples(expected));

  // No rank holds more than its part and the halo it reports; with several ranks, not the whole.
  const std::int32_t held = mesh.mesh().num_vertices();
  EXPECT_LE(held - mesh.owned_count(), mesh.quality().halo_max);
  EXPECT_LE(mesh.local_count() - mesh.owned_count(), mesh.quality().ghosts_max);
  if (comm.size > 1) {
    EXPECT_LT(held, n);
  }
  for (std::int32_t local = 0; local < held; ++local)
    ASSERT_EQ(mesh.local_index(mesh.global_index(local)), local);

  // Refined on the parts, every vertex the rank holds is the serial refinement's, bit for bit.
  for (std::int32_t local = 0; local < held; ++local)
    ASSERT_EQ(mesh.mesh().positions[local], input.positions[mesh.input_id()[local]])
        << "vertex " << mesh.input_id()[local];

  // The halo is complete: owned vertices, ghosts and the next ring keep all their triangles.
  const MeshTopology whole(input);

  // Every edge the rank holds has the serial refinement's crease flag, and each is counted once.
  ASSERT_EQ(mesh.creases().empty(), fine_creases.empty());
  EXPECT_EQ(crease_edge_count(mesh), std::count(fine_creases.begin(), fine_creases.end(), 1));
  if (!fine_creases.empty()) {
    ASSERT_EQ(mesh.creases().size(), std::size_t(mesh.topology().num_edges()));
    for (std::int32_t e = 0; e < mesh.topology().num_edges(); ++e) {
      const auto [a, b] = mesh.topology().edges()[e];
      const std::int32_t serial =
          whole.find_edge(std::int32_t(mesh.input_id()[a]), std::int32_t(mesh.input_id()[b]));
      ASSERT_EQ(mesh.creases()[std::size_t(e)], fine_creases[std::size_t(serial)])
          << "edge " << mesh.input_id()[a] << "-" << mesh.input_id()[b];
    }
  }
  std::vector<int> depth(std::size_t(held), -1);
  std::vector<std::int32_t> ring(std::size_t(mesh.owned_count()));
  std::iota(ring.begin(), ring.end(), 0);
  for (const std::int32_t v : ring)
    depth[v] = 0;
  for (int d = 1; d < DistributedMesh::kHaloRings; ++d) {
    std::vector<std::int32_t> next;
    for (const std::int32_t v : ring)
      for (const std::int32_t w : mesh.topology().vertex_neighbors().row(v))
        if (depth[w] < 0) {
          depth[w] = d;
          next.push_back(w);
        }
    ring = next;
  }
  for (std::int32_t v = 0; v < held; ++v)
    if (depth[v] >= 0) {
      ASSERT_EQ(mesh.topology().vertex_triangles().row(v).size(),
                whole.vertex_triangles().row(std::int32_t(mesh.input_id()[v])).size())
          << "vertex " << v << " at ring " << depth[v];
    }
  for (std::int32_t v = 0; v < mesh.local_count(); ++v)
    ASSERT_TRUE(depth[v] == 0 || depth[v] == 1) << "a ghost is not a neighbour of an owned vertex";

  // Curvature on the part equals curvature on the whole surface at owned vertices.
  const auto serial = principal_curvatures(input, whole);
  const auto local = principal_curvatures(mesh.mesh(), mesh.topology());
  double largest = 0, scale = 0;
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v) {
    const auto& reference = serial[std::size_t(mesh.input_id()[v])];
    largest = std::max(
        {largest, std::abs(local[v].k1 - reference.k1), std::abs(local[v].k2 - reference.k2)});
    scale = std::max({scale, std::abs(reference.k1), std::abs(reference.k2)});
  }
  EXPECT_LE(largest, 1e-9 * scale);

  // Sums over the surface equal the serial ones.
  EXPECT_NEAR(total_area(mesh), total_area(input), 1e-12 * total_area(input));
  EXPECT_NEAR(mean_edge_length(mesh), mean_edge_length(input), 1e-12 * mean_edge_length(input));
}

void check_halo_update(const TriangleMesh& input) {
  const DistributedMesh mesh(par::world(), input, PartitionMethod::kMorton);
  const std::size_t held = mesh.mesh().positions.size();
  std::vector<double> values(2 * held, -1.0);
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v) {
    values[2 * v] = double(mesh.input_id()[v]);
    values[2 * v + 1] = -3.0 * double(mesh.input_id()[v]);
  }
  mesh.update_halo(values, 2);
  for (std::size_t v = 0; v < held; ++v) {
    ASSERT_EQ(values[2 * v], double(mesh.input_id()[v]));
    ASSERT_EQ(values[2 * v + 1], -3.0 * double(mesh.input_id()[v]));
  }
}

TEST(DistributedMesh, EachRankHoldsItsPartAndACompleteHalo) {
  const auto sphere = noisy(icosphere(4), 0.02, 3);
  check_ownership(sphere, PartitionMethod::kMorton);
  check_ownership(sphere, PartitionMethod::kScotch);
}

// Refinement on the parts: Loop rounds (n = 2 and 4: three and two coarse rings of halo) and
// sphere rounds (n = 8: one ring), on a noisy sphere and on an open noisy square.
TEST(DistributedMesh, RefiningThePartsGivesTheSerialRefinement) {
  const auto sphere = noisy(icosphere(2), 0.05, 5);
  check_ownership(sphere, PartitionMethod::kMorton, rounds(1));
  check_ownership(sphere, PartitionMethod::kScotch, rounds(2));
  const RefinementStep on_sphere{RefinementStep::Rule::kSphere, {0, 0, 0}, 2.0};
  check_ownership(icosphere(1, 2.0), PartitionMethod::kMorton, rounds(3, on_sphere));
  check_ownership(noisy(plane(Vec3(1, 1, 0), 8), 0.05, 6), PartitionMethod::kMorton, rounds(2));
  // A cube's edges as creases, their corners fixed: the parts keep them as the serial rounds do.
  const auto cube = noisy(box(Vec3(1, 1, 1), 8), 0.03, 8);
  const auto cube_creases = crease_edges(cube, MeshTopology(cube), 45.0);
  check_ownership(cube, PartitionMethod::kScotch, rounds(2), cube_creases);
  check_ownership(cube, PartitionMethod::kMorton, {}, cube_creases);
}

TEST(DistributedMesh, UpdateHaloBringsTheOwnersValues) {
  check_halo_update(icosphere(4));
}

TEST(DistributedMeshOnRealData, TheRawBunnyWithItsHolesSplitsExactly) {
  const auto path = test::real_data("meshes/bunny00.off");
  if (path.empty())
    GTEST_SKIP() << test::missing_data_message("meshes/bunny00.off");
  const auto bunny = read_raw_mesh(path);
  check_ownership(bunny, PartitionMethod::kScotch);
  check_ownership(bunny, PartitionMethod::kMorton, rounds(1));
  check_halo_update(bunny);
}

} // namespace
} // namespace texsim::geom
