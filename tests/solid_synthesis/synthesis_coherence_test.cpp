// The incoherent-voxel fraction: 0 for a shifted copy of the exemplar (and for a copy stretched or
// turned by the field's Jacobian, whole-voxel or sub-voxel), exactly one voxel for a single speck,
// nearly all for random coordinates, the same at any rank count.
#include "pipelines/solid_synthesis/synthesis_coherence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <type_traits>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr int kLevel = 4; // 16^3
constexpr int kSize = 1 << kLevel;
const vol::Dims kExemplar{32, 32, 32};

template <class Value>
double fraction_of(const Value& value, const LevelJacobians* jacobians = nullptr) {
  const par::Comm comm = par::world();
  CoordinateSlab slab(level_layout(kLevel, comm.rank, comm.size));
  const LevelLayout& layout = slab.layout();
  for (int k = layout.z_begin; k < layout.z_end; ++k)
    for (int j = 0; j < kSize; ++j)
      for (int i = 0; i < kSize; ++i)
        if constexpr (std::is_same_v<decltype(value(i, j, k)), Coord>)
          slab.at(i, j, k) = Position::at_voxel(value(i, j, k));
        else
          slab.at(i, j, k) = value(i, j, k);
  slab.exchange_halo(comm);
  return incoherent_fraction(comm, slab, jacobians, kExemplar, {kSize, kSize, kSize});
}

TEST(IncoherentFraction, ZeroForACopyOneVoxelForASpeckNearlyAllForNoise) {
  EXPECT_EQ(fraction_of([](int i, int j, int k) { return Coord{i + 5, j + 30, k + 17}; }), 0.0);
  EXPECT_EQ(fraction_of([](int i, int j, int k) {
              return i == 3 && j == 4 && k == 5 ? Coord{20, 20, 20} : Coord{i, j, k};
            }),
            1.0 / (kSize * kSize * kSize));
  const double noise = fraction_of([](int i, int j, int k) {
    std::mt19937 rng(std::uint32_t(i + kSize * (j + kSize * k)));
    std::uniform_int_distribution<int> coordinate(0, 31);
    return Coord{coordinate(rng), coordinate(rng), coordinate(rng)};
  });
  EXPECT_GT(noise, 0.99);
}

TEST(IncoherentFraction, TheJacobianSaysWhatContinuesAVoxel) {
  // A = 2 I: a coherent anisometric copy steps by 2 exemplar voxels per output voxel.
  const par::Comm comm = par::world();
  const LevelLayout layout = level_layout(kLevel, comm.rank, comm.size);
  LevelJacobians doubled = sample_level(*identity_field(), kSize, layout.z_begin - kSlabHalo,
                                        layout.z_end + kSlabHalo, kSize);
  for (auto& a : doubled.jacobian)
    a *= 2.0f;
  const auto stretched = [](int i, int j, int k) { return Coord{2 * i, 2 * j, 2 * k}; };
  EXPECT_EQ(fraction_of(stretched, &doubled), 0.0);
  EXPECT_EQ(fraction_of(stretched), 1.0); // read isometrically, no neighbour continues
}

TEST(IncoherentFraction, RotatedCopiesAreCoherentRoundedOrNot) {
  // S(p) = round(A p + c) with A a 30 degree rotation: the rounding makes S(p + e) - S(p) either
  // rounding of A e, and every voxel is still part of one coherent copy. The same copy kept to
  // 1/256 voxel, as the synthesis keeps positions, is coherent too.
  const par::Comm comm = par::world();
  const LevelLayout layout = level_layout(kLevel, comm.rank, comm.size);
  const LevelJacobians turned =
      sample_level(*rotation_field(Eigen::Vector3d::UnitZ(), 30.0), kSize,
                   layout.z_begin - kSlabHalo, layout.z_end + kSlabHalo, kSize);
  const Eigen::Matrix3f a = turned.a(0, 0, layout.z_begin);
  for (const int bits : {0, kSubvoxelBits}) {
    const float scale = float(1 << bits);
    const auto copy = [&](int i, int j, int k) {
      const Eigen::Vector3f s = scale * (a * Eigen::Vector3f(float(i), float(j), float(k)) +
                                         Eigen::Vector3f(3.3f, 7.6f, 1.2f));
      const Position rounded{int(std::floor(s.x() + 0.5f)), int(std::floor(s.y() + 0.5f)),
                             int(std::floor(s.z() + 0.5f))};
      return bits == 0 ? Position::at_voxel({rounded.x, rounded.y, rounded.z}) : rounded;
    };
    const double fraction = fraction_of(copy, &turned);
    std::printf("rotated copy kept to 2^-%d voxel: %.4f incoherent\n", bits, fraction);
    EXPECT_EQ(fraction, 0.0);
  }
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
