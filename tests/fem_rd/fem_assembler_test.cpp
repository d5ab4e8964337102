// Assembly in both bases (P1 hats, Loop's box splines): the mass matrix integrates 1 to the
// surface's area (consistent and lumped), the stiffness matrix's rows sum to zero (constants are
// harmonic), and the values are the same bytes whatever the number of OpenMP threads (each value
// sums its elements in element order).
#include "geom/crease_edges.hpp"
#include "geom/distributed_measures.hpp"
#include "geom/generators.hpp"
#include "par/comm.hpp"
#include "par/petsc_session.hpp"
#include "pipelines/fem_rd/loop_assembler.hpp"
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

template <class Assembler> Assembled assemble(const geom::DistributedMesh& mesh, int threads) {
  omp_set_num_threads(threads);
  const Assembler assembler(mesh);
  std::vector<double> weight(std::size_t(assembler.coefficient_count())),
      tensors(9 * weight.size());
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

/// K 1 = 0: constants are harmonic, every row of the stiffness matrix sums to zero.
template <class Assembler>
void expect_rows_sum_to_zero(const par::Comm& comm, const geom::DistributedMesh& mesh,
                             const std::vector<double>& stiffness_values) {
  const Assembler assembler(mesh);
  ASSERT_EQ(stiffness_values.size(), assembler.value_count());
  par::PetscMat stiffness = assembler.create_matrix(comm);
  assembler.set_values(stiffness, stiffness_values);
  par::PetscVec ones, product;
  TEXSIM_PETSC_CALL(MatCreateVecs(stiffness, ones.address(), product.address()));
  TEXSIM_PETSC_CALL(VecSet(ones, 1.0));
  TEXSIM_PETSC_CALL(MatMult(stiffness, ones, product));
  double largest_row = 0.0, largest_entry = 0.0;
  TEXSIM_PETSC_CALL(VecNorm(product, NORM_INFINITY, &largest_row));
  TEXSIM_PETSC_CALL(MatNorm(stiffness, NORM_MAX, &largest_entry));
  EXPECT_LT(largest_row, 1e-12 * largest_entry);
}

template <class Assembler> class FemAssemblerTest : public ::testing::Test {};
using Bases = ::testing::Types<P1Assembler, LoopAssembler>;
TYPED_TEST_SUITE(FemAssemblerTest, Bases);

TYPED_TEST(FemAssemblerTest, MassIntegratesTheAreaAndStiffnessRowsSumToZero) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(3), geom::PartitionMethod::kMorton);
  const auto values = assemble<TypeParam>(mesh, 2);
  const double area = geom::total_area(mesh);
  const double mass = global_sum(values.mass);
  EXPECT_NEAR(global_sum(values.lumped), mass, 1e-12 * area);
  if constexpr (std::is_same_v<TypeParam, P1Assembler>)
    EXPECT_NEAR(mass, area, 1e-12 * area);
  else // the limit surface lies inside the icosphere's polyhedron
    EXPECT_NEAR(mass / area, 0.985, 0.01);
  expect_rows_sum_to_zero<TypeParam>(comm, mesh, values.stiffness);
}

TYPED_TEST(FemAssemblerTest, OnAFlatSquareMassIsAtMostItsAreaAndStiffnessRowsSumToZero) {
  // An open surface: P1 integrates the unit square exactly; Loop's boundary rules make the
  // boundary the cubic B-spline of its vertices, inside the square (rounded at the corners).
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::plane(geom::Vec3(1, 1, 0), 16),
                                   geom::PartitionMethod::kScotch);
  const auto values = assemble<TypeParam>(mesh, 2);
  const double mass = global_sum(values.mass);
  EXPECT_NEAR(global_sum(values.lumped), mass, 1e-12);
  if constexpr (std::is_same_v<TypeParam, P1Assembler>) {
    EXPECT_NEAR(mass, 1.0, 1e-12);
  } else {
    EXPECT_LT(mass, 1.0 - 1e-6);
    EXPECT_GT(mass, 0.995);
  }
  expect_rows_sum_to_zero<TypeParam>(comm, mesh, values.stiffness);
}

TEST(LoopCreases, AFoldKeptSharpKeepsItsArea) {
  // A 2 x 1 square folded by 90 degrees along x = 1: with the fold's edges as creases the limit
  // surface is the two flat halves (rounded only at the outer corners); without, the fold is
  // rounded off and the area falls.
  geom::TriangleMesh folded = geom::plane(geom::Vec3(2, 1, 0), 16);
  for (auto& p : folded.positions)
    p = p.x() <= 1.0 ? p : geom::Vec3(1.0, p.y(), p.x() - 1.0);
  const par::Comm comm = par::world();
  const auto area = [&](double crease_angle) {
    const geom::DistributedMesh mesh(
        comm, folded, geom::PartitionMethod::kScotch, {},
        geom::crease_edges(folded, geom::MeshTopology(folded), crease_angle));
    const LoopAssembler assembler(mesh);
    return global_sum(assembler.mass_values({}, false));
  };
  const double sharp = area(45.0), smooth = area(180.0);
  EXPECT_LT(sharp, 2.0);
  EXPECT_GT(sharp, 1.99);
  EXPECT_LT(smooth, sharp - 0.005);
}

TYPED_TEST(FemAssemblerTest, SameBytesForAnyThreadCount) {
  const par::Comm comm = par::world();
  const geom::DistributedMesh mesh(comm, geom::icosphere(4), geom::PartitionMethod::kScotch);
  const auto one = assemble<TypeParam>(mesh, 1), three = assemble<TypeParam>(mesh, 3);
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
