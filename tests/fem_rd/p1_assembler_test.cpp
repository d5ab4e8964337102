// P1 assembly: the mass matrix integrates 1 to the surface's area (consistent and lumped), the
// stiffness matrix's rows sum to zero (constants are harmonic), and the values are the same
// bytes whatever the number of OpenMP threads (each value sums its elements in element order).
#include "geom/distributed_measures.hpp"
#include "geom/generators.hpp"
#include "par/comm.hpp"
#include "pipelines/fem_rd/p1_assembler.hpp"

#include <gtest/gtest.h>
#include <mpi.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <numeric>

namespace texsim::pipelines::fem_rd {
namespace {

struct Assembled {
  std::vector<double> mass, lumped, weighted, stiffness, anisotropic;
};

Assembled assemble(const geom::DistributedMesh& mesh, int threads) {
  omp_set_num_threads(threads);
  const P1Assembler assembler(mesh);
  std::vector<double> weight(std::size_t(mesh.local_count())), tensors(9 * weight.size());
  for (std::size_t v = 0; v < weight.size(); ++v) {
    const double x = double(mesh.global_index(std::int32_t(v)));
    weight[v] = 1.0 + 0.5 * std::sin(x);
    // A symmetric tensor that varies from vertex to vertex.
    const double a = 1.0 + 0.3 * std::cos(x), b = 0.2 * std::sin(2 * x);
    const double t[9] = {a, b, 0, b, 2 - a, 0.1, 0, 0.1, 1};
    std::memcpy(&tensors[9 * v], t, sizeof t);
  }
  return {assembler.mass_values({}, false), assembler.mass_values({}, true),
          assembler.mass_values(weight, false), assembler.stiffness_values({}),
          assembler.stiffness_values(tensors)};
}

double global_sum(const std::vector<double>& values) {
  double local = std::accumulate(values.begin(), values.end(), 0.0), total = 0.0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return total;
}

TEST(P1Assembler, MassIntegratesTheAreaAndStiffnessRowsSumToZero) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(3), geom::PartitionMethod::kMorton);
  const auto values = assemble(mesh, 2);
  const double area = geom::total_area(mesh);
  EXPECT_NEAR(global_sum(values.mass), area, 1e-12 * area);
  EXPECT_NEAR(global_sum(values.lumped), area, 1e-12 * area);
  const P1Assembler assembler(mesh);
  ASSERT_EQ(values.stiffness.size(), assembler.value_count());
  // Rows are contiguous in the values: the row sums of K are K 1 = 0.
  double largest_row = 0.0, largest_entry = 0.0;
  const auto& stiffness = values.stiffness;
  std::size_t at = 0;
  for (std::int32_t row = 0; row < mesh.owned_count(); ++row) {
    const auto degree = std::size_t(mesh.topology().vertex_neighbors().row(row).size()) + 1;
    double sum = 0.0;
    for (std::size_t k = 0; k < degree; ++k, ++at) {
      sum += stiffness[at];
      largest_entry = std::max(largest_entry, std::abs(stiffness[at]));
    }
    largest_row = std::max(largest_row, std::abs(sum));
  }
  EXPECT_EQ(at, stiffness.size());
  EXPECT_LT(largest_row, 1e-12 * largest_entry);
}

TEST(P1Assembler, SameBytesForAnyThreadCount) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(4), geom::PartitionMethod::kScotch);
  const auto one = assemble(mesh, 1), three = assemble(mesh, 3);
  const auto same = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
  };
  EXPECT_TRUE(same(one.mass, three.mass));
  EXPECT_TRUE(same(one.lumped, three.lumped));
  EXPECT_TRUE(same(one.weighted, three.weighted));
  EXPECT_TRUE(same(one.stiffness, three.stiffness));
  EXPECT_TRUE(same(one.anisotropic, three.anisotropic));
}

} // namespace
} // namespace texsim::pipelines::fem_rd
