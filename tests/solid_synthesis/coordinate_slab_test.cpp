#include "pipelines/solid_synthesis/anisometric_field.hpp"
#include "pipelines/solid_synthesis/coordinate_slab.hpp"
#include "pipelines/solid_synthesis/correction_stencil.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// A value that names voxel (i, j, k) of a level of size n uniquely.
Position label(int i, int j, int k, int n) {
  return {i, j, k + 1000 * n};
}

/// c voxels in fixed point.
Position fixed(const Coord& c) {
  return Position::at_voxel(c);
}

TEST(LevelLayout, SlabsTileEachLevelEvenlyOverAsManyRanksAsItHasPairsOfPlanes) {
  for (int ranks = 1; ranks <= 9; ++ranks)
    for (int level = 0; level <= 9; ++level) {
      const int n = 1 << level;
      // Only the levels of 1 and 2 voxels are replicated (on more than one rank).
      const bool replicated = level_layout(level, 0, ranks).replicated;
      EXPECT_EQ(replicated, ranks == 1 || n < 2 * kSlabHalo) << n << " at " << ranks << " ranks";
      const int active = replicated ? 1 : std::min(ranks, n / kSlabHalo);
      int next = 0, thinnest = n, thickest = 0;
      for (int r = 0; r < ranks; ++r) {
        const LevelLayout layout = level_layout(level, r, ranks);
        EXPECT_EQ(layout.size, n);
        EXPECT_EQ(layout.replicated, replicated);
        if (replicated) {
          EXPECT_EQ(layout.z_begin, 0);
          EXPECT_EQ(layout.z_end, n);
          continue;
        }
        EXPECT_EQ(layout.ranks, active);
        if (r >= active) { // waits: no plane
          EXPECT_EQ(layout.z_begin, n);
          EXPECT_EQ(layout.z_end, n);
          continue;
        }
        EXPECT_EQ(layout.z_begin, next);
        next = layout.z_end;
        thinnest = std::min(thinnest, layout.z_end - layout.z_begin);
        thickest = std::max(thickest, layout.z_end - layout.z_begin);
      }
      if (!replicated) {
        EXPECT_EQ(next, n) << n << " at " << ranks << " ranks";
        EXPECT_GE(thinnest, kSlabHalo);
        EXPECT_LE(thickest - thinnest, 1) << n << " at " << ranks << " ranks";
      }
    }
}

TEST(CoordinateSlab, ParentPlanesAreTheParentsOfTheOwnedPlanes) {
  const par::Comm comm = par::world();
  for (int level = 1; level <= 6; ++level) {
    CoordinateSlab parent(level_layout(level - 1, comm.rank, comm.size));
    const LevelLayout& above = parent.layout();
    for (int k = above.z_begin; k < above.z_end; ++k)
      for (int j = 0; j < above.size; ++j)
        for (int i = 0; i < above.size; ++i)
          parent.at(i, j, k) = label(i, j, k, above.size);
    const LevelLayout child = level_layout(level, comm.rank, comm.size);
    const CoordinateSlab planes = parent_planes(comm, parent, child);
    for (int k = child.z_begin; k < child.z_end; ++k)
      for (int j = 0; j < child.size; ++j)
        for (int i = 0; i < child.size; ++i)
          ASSERT_EQ(planes.at(i >> 1, j >> 1, k >> 1), label(i >> 1, j >> 1, k >> 1, above.size))
              << "level " << level << " voxel " << i << " " << j << " " << k;
  }
}

TEST(CoordinateSlab, HaloHoldsThePeriodicNeighbourPlanes) {
  const par::Comm comm = par::world();
  for (int level : {0, 1, 2, 4, 5}) {
    CoordinateSlab slab(level_layout(level, comm.rank, comm.size));
    const LevelLayout& layout = slab.layout();
    const int n = layout.size;
    for (int k = layout.z_begin; k < layout.z_end; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          slab.at(i, j, k) = label(i, j, k, n);
    slab.exchange_halo(comm);
    if (layout.z_begin == layout.z_end)
      continue; // a rank the level does not need: no planes, no halo
    for (int k = layout.z_begin - kSlabHalo; k < layout.z_end + kSlabHalo; ++k)
      for (int j = -2; j < n + 2; ++j)
        for (int i = -2; i < n + 2; ++i)
          ASSERT_EQ(slab.at(i, j, k),
                    label(((i % n) + n) % n, ((j % n) + n) % n, ((k % n) + n) % n, n))
              << "level " << level << " voxel " << i << " " << j << " " << k;
  }
}

TEST(CorrectionStencil, IsometricStencilIsEquationFour) {
  for (int h : {1, 2, 8}) {
    const CorrectionStencil stencil =
        make_stencil(h, Eigen::Matrix3f::Identity(), Eigen::Matrix3f::Identity());
    for (int d = 0; d < kDiagonalCount; ++d) {
      const Coord delta{d & 1 ? 1 : -1, d & 2 ? 1 : -1, d & 4 ? 1 : -1};
      EXPECT_EQ(stencil.source[d], delta);
      EXPECT_EQ(stencil.source_shift[d], fixed(Coord{h * delta.x, h * delta.y, h * delta.z}));
      EXPECT_EQ(stencil.exemplar_offset[d], (Coord{h * delta.x, h * delta.y, h * delta.z}));
      // N(p; Delta) = 1/4 sum_M V[S[p + Delta + M Delta] - h M Delta].
      const Coord m_delta[4] = {{0, 0, 0}, {delta.x, 0, 0}, {0, delta.y, 0}, {0, 0, delta.z}};
      for (int m = 0; m < kSubNeighbourCount; ++m) {
        EXPECT_EQ(stencil.sample[d][m], delta + m_delta[m]);
        EXPECT_EQ(stencil.sample_shift[d][m],
                  fixed(Coord{-h * m_delta[m].x, -h * m_delta[m].y, -h * m_delta[m].z}));
      }
    }
  }
}

TEST(CorrectionStencil, RotationTurnsTheNeighbourDirections) {
  // A quarter turn about z: the field's axes are R, the Jacobian R^-1. The neighbour that stands
  // for exemplar direction Delta sits at R Delta in the output.
  const Eigen::Matrix3f rotation =
      Eigen::AngleAxisf(float(M_PI / 2), Eigen::Vector3f::UnitZ()).toRotationMatrix();
  const CorrectionStencil stencil = make_stencil(1, rotation.inverse(), rotation);
  for (int d = 0; d < kDiagonalCount; ++d) {
    const Eigen::Vector3f delta(d & 1 ? 1 : -1, d & 2 ? 1 : -1, d & 4 ? 1 : -1);
    const Eigen::Vector3f turned = rotation * delta;
    EXPECT_EQ(stencil.source[d], (Coord{int(std::lround(turned.x())), int(std::lround(turned.y())),
                                        int(std::lround(turned.z()))}));
    // Reading through the rotated neighbour predicts p's coordinate as S[q] - Delta.
    EXPECT_EQ(stencil.source_shift[d],
              fixed(Coord{int(delta.x()), int(delta.y()), int(delta.z())}));
  }
}

/// Eqs. (6)-(7) written out entry by entry, one Eigen product, normalisation and std::floor
/// each: what make_stencil's batched evaluation must reproduce bit for bit.
CorrectionStencil literal_stencil(int h, const Eigen::Matrix3f& a, const Eigen::Matrix3f& a_inverse,
                                  const NeighbourJacobian& neighbour = {}) {
  const auto rounded = [](const Eigen::Vector3f& v) {
    return Coord{static_cast<std::int32_t>(std::floor(v.x() + 0.5f)),
                 static_cast<std::int32_t>(std::floor(v.y() + 0.5f)),
                 static_cast<std::int32_t>(std::floor(v.z() + 0.5f))};
  };
  const auto warped = [&](const Eigen::Vector3f& d) {
    const Eigen::Vector3f phi = a_inverse * d;
    const float length = phi.norm();
    return length > 0.0f ? rounded(phi / length) : rounded(d.normalized());
  };
  // h A o in fixed point, A the mean of the two ends' Jacobians with `neighbour`.
  const auto shift = [&](const Coord& o) {
    const Eigen::Matrix3f m = neighbour ? Eigen::Matrix3f((a + neighbour(o)) * 0.5f) : a;
    const Coord c = rounded(static_cast<float>(h << kSubvoxelBits) *
                            (m * Eigen::Vector3f(float(o.x), float(o.y), float(o.z))));
    return Position{c.x, c.y, c.z};
  };
  CorrectionStencil stencil;
  for (int d = 0; d < kDiagonalCount; ++d) {
    const Eigen::Vector3f delta(d & 1 ? 1.0f : -1.0f, d & 2 ? 1.0f : -1.0f, d & 4 ? 1.0f : -1.0f);
    const Coord h_delta{h * int(delta.x()), h * int(delta.y()), h * int(delta.z())};
    stencil.exemplar_offset[d] = h_delta;
    stencil.source[d] = warped(delta);
    stencil.source_shift[d] = shift(stencil.source[d]);
    for (int m = 0; m < kSubNeighbourCount; ++m) {
      Eigen::Vector3f m_delta = Eigen::Vector3f::Zero();
      if (m > 0)
        m_delta[m - 1] = delta[m - 1];
      const Coord offset = stencil.source[d] + (m > 0 ? warped(m_delta) : Coord{});
      stencil.sample[d][m] = offset;
      stencil.sample_shift[d][m] = fixed(h_delta) - shift(offset);
    }
  }
  return stencil;
}

void expect_same_stencil(const CorrectionStencil& actual, const CorrectionStencil& expected,
                         const Eigen::Matrix3f& a_inverse, int h) {
  for (int d = 0; d < kDiagonalCount; ++d) {
    EXPECT_EQ(actual.source[d], expected.source[d]) << "h " << h << ", A^-1\n" << a_inverse;
    EXPECT_EQ(actual.source_shift[d], expected.source_shift[d]) << "h " << h << ", A^-1\n"
                                                                << a_inverse;
    EXPECT_EQ(actual.exemplar_offset[d], expected.exemplar_offset[d]);
    for (int m = 0; m < kSubNeighbourCount; ++m) {
      EXPECT_EQ(actual.sample[d][m], expected.sample[d][m]) << "h " << h << ", A^-1\n" << a_inverse;
      EXPECT_EQ(actual.sample_shift[d][m], expected.sample_shift[d][m]) << "h " << h << ", A^-1\n"
                                                                        << a_inverse;
    }
  }
}

TEST(CorrectionStencil, MatchesTheLiteralFormulaBitForBit) {
  // Frames F = A^-1 as sample_level makes them (|det| >= kSingularFrameDeterminant): rotations
  // (the built-in fields), general frames with scale and shear, frames with entries on a 1/4
  // grid, whose products h A o land exactly on rounding boundaries, and frames whose x axis
  // (1, sqrt(3) cos t, sqrt(3) sin t) normalises to x = 1/2 give or take the rounding of |.|.
  std::mt19937 rng(2008);
  std::uniform_real_distribution<float> entry(-2.0f, 2.0f);
  int compared = 0;
  for (int trial = 0; trial < 8000; ++trial) {
    Eigen::Matrix3f frame;
    for (int e = 0; e < 9; ++e)
      frame(e) = entry(rng);
    if (trial % 4 == 0) {
      const Eigen::Vector3f axis(entry(rng), entry(rng), entry(rng));
      if (!(axis.norm() > 0.0f))
        continue;
      frame = Eigen::AngleAxisf(2.0f * entry(rng), axis.normalized()).toRotationMatrix();
    } else if (trial % 4 == 2) {
      frame = (4.0f * frame).array().round() / 4.0f;
    } else if (trial % 4 == 3) {
      const float t = 2.0f * entry(rng);
      frame.col(0) =
          Eigen::Vector3f(1.0f, std::sqrt(3.0f) * std::cos(t), std::sqrt(3.0f) * std::sin(t));
    }
    if (!(std::abs(frame.determinant()) >= kSingularFrameDeterminant))
      continue;
    const Eigen::Matrix3f jacobian = frame.inverse();
    // A field that turns: A_q = A rotated a little, by an angle that depends on q - p.
    std::array<Eigen::Matrix3f, 125> turned;
    for (int o = 0; o < 125; ++o)
      turned[o] =
          jacobian * Eigen::AngleAxisf(0.01f * float(o + trial % 7), Eigen::Vector3f::UnitZ())
                         .toRotationMatrix();
    const NeighbourJacobian turning = [&](const Coord& o) -> const Eigen::Matrix3f& {
      return turned.at(std::size_t((o.x + 2) + 5 * ((o.y + 2) + 5 * (o.z + 2))));
    };
    const NeighbourJacobian constant = [&](const Coord&) -> const Eigen::Matrix3f& {
      return jacobian;
    };
    for (int h : {1, 2, 8, 64}) {
      expect_same_stencil(make_stencil(h, jacobian, frame), literal_stencil(h, jacobian, frame),
                          frame, h);
      expect_same_stencil(make_stencil(h, jacobian, frame, turning),
                          literal_stencil(h, jacobian, frame, turning), frame, h);
      // A uniform field: the same bits as the stencil without neighbours.
      expect_same_stencil(make_stencil(h, jacobian, frame, constant),
                          make_stencil(h, jacobian, frame), frame, h);
      if (::testing::Test::HasFailure())
        return;
    }
    ++compared;
  }
  EXPECT_GT(compared, 7000);
}

TEST(ChildOffsets, IsometricChildrenAreSpacedByH) {
  for (int h : {1, 2, 4}) {
    const auto offsets = child_offsets(h, Eigen::Matrix3f::Identity());
    for (int c = 0; c < 8; ++c) {
      const Position expected =
          offsets[0] + fixed(Coord{h * (c & 1), h * ((c >> 1) & 1), h * (c >> 2)});
      EXPECT_EQ(offsets[c], expected) << "h " << h << " child " << c;
    }
  }
}

} // namespace
} // namespace texsim::pipelines::solid_synthesis
