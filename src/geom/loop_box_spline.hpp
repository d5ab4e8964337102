#pragma once
/// The twelve functions of a regular Loop patch: the quartic three-direction box spline that the
/// limit of Loop subdivision is on a triangle whose three corners have valence 6 (Loop 1987;
/// Stam 1998 evaluates them the same way). Points of the patch triangle (a, b, c) are
/// x = a + s (b - a) + t (c - a), s, t >= 0, s + t <= 1.
#include <array>

namespace texsim::geom {

/// Lattice coordinates of the twelve control points, in the order of the functions: corner a at
/// (0, 0), b at (1, 0), c at (0, 1), then the rest of the corners' 1-rings. A point (i, j) sits at
/// a + i (b - a) + j (c - a) on the regular triangular lattice.
inline constexpr std::array<std::array<int, 2>, 12> kRegularPatchLattice{{{0, 0},
                                                                          {1, 0},
                                                                          {0, 1},
                                                                          {-1, 1},
                                                                          {-1, 0},
                                                                          {0, -1},
                                                                          {1, -1},
                                                                          {2, 0},
                                                                          {1, 1},
                                                                          {2, -1},
                                                                          {0, 2},
                                                                          {-1, 2}}};

/// Values and derivatives in s and t of the twelve functions at one point.
struct RegularPatchBasis {
  std::array<double, 12> value{};
  std::array<double, 12> d_s{};
  std::array<double, 12> d_t{};
};

/// The twelve functions at (s, t). They sum to 1 and reproduce cubic polynomials.
RegularPatchBasis regular_patch_basis(double s, double t);

} // namespace texsim::geom
