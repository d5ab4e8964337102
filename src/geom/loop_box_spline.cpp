#include "geom/loop_box_spline.hpp"

namespace texsim::geom {
namespace {

/// Monomials s^a t^b of degree <= 4, in the order of the coefficient table.
constexpr std::array<std::array<int, 2>, 15> kMonomials{{{0, 0},
                                                         {0, 1},
                                                         {0, 2},
                                                         {0, 3},
                                                         {0, 4},
                                                         {1, 0},
                                                         {1, 1},
                                                         {1, 2},
                                                         {1, 3},
                                                         {2, 0},
                                                         {2, 1},
                                                         {2, 2},
                                                         {3, 0},
                                                         {3, 1},
                                                         {4, 0}}};

/// 12 x the coefficient of each monomial in each function (rows in kRegularPatchLattice order).
/// Obtained by refining a unit control value twice with Loop's regular masks (even 5/8, 1/16;
/// odd 3/8, 1/8), taking the limit mask (1/2, 1/12) at the 15 points (i/4, j/4) of the patch and
/// interpolating the quartic through them; tests/geom/loop_patch_basis_test.cpp checks the result
/// against the limit of geom::loop_subdivide at other points.
constexpr int kCoefficients[12][15] = {{6, 0, -12, 8, -1, 0, -12, 12, -2, -12, 12, 0, 8, -2, -1},
                                       {1, 2, 0, -4, 2, 4, 6, -12, 4, 6, -6, 0, -4, -2, -1},
                                       {1, 4, 6, -4, -1, 2, 6, -6, -2, 0, -12, 0, -4, 4, 2},
                                       {1, 2, 0, -4, 2, -2, -6, 0, 4, 0, 6, 0, 2, -2, -1},
                                       {1, -2, 0, 2, -1, -4, 6, 0, -2, 6, -6, 0, -4, 2, 1},
                                       {1, -4, 6, -4, 1, -2, 6, -6, 2, 0, 0, 0, 2, -2, -1},
                                       {1, -2, 0, 2, -1, 2, -6, 6, -2, 0, 0, 0, -4, 4, 2},
                                       {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 1},
                                       {0, 0, 0, 2, -1, 0, 0, 6, -2, 0, 6, 0, 2, -2, -1},
                                       {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, -2, -1},
                                       {0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0},
                                       {0, 0, 0, 2, -1, 0, 0, 0, -2, 0, 0, 0, 0, 0, 0}};

} // namespace

RegularPatchBasis regular_patch_basis(double s, double t) {
  std::array<double, 5> s_power{1, s, s * s, s * s * s, s * s * s * s};
  std::array<double, 5> t_power{1, t, t * t, t * t * t, t * t * t * t};
  RegularPatchBasis basis;
  for (int f = 0; f < 12; ++f) {
    double value = 0, d_s = 0, d_t = 0;
    for (int m = 0; m < 15; ++m) {
      const auto [a, b] = kMonomials[m];
      const double c = kCoefficients[f][m] / 12.0;
      value += c * s_power[a] * t_power[b];
      if (a > 0)
        d_s += c * a * s_power[a - 1] * t_power[b];
      if (b > 0)
        d_t += c * b * s_power[a] * t_power[b - 1];
    }
    basis.value[f] = value;
    basis.d_s[f] = d_s;
    basis.d_t[f] = d_t;
  }
  return basis;
}

} // namespace texsim::geom
