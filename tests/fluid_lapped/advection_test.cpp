// Advection of patches: a reversing plane vortex brings a patch back to where it started within
// 1e-3 r, with the error falling as RK4's fourth order says when the substeps double; the
// reversing zonal shear on a faceted sphere brings it back within 5% of an edge; a strain flow
// erodes a patch until every triangle is past delta_max, and then every texel of it is eroded; a
// velocity grid series is trilinear in world space and linear in time.
#include "geom/generators.hpp"
#include "pipelines/fluid_lapped/analytic_flows.hpp"
#include "pipelines/fluid_lapped/erosion_mask.hpp"
#include "pipelines/fluid_lapped/fluid_frames.hpp"
#include "pipelines/fluid_lapped/patch_advection.hpp"
#include "pipelines/fluid_lapped/patch_builder.hpp"
#include "pipelines/fluid_lapped/patch_distortion.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace texsim::pipelines::fluid_lapped {
namespace {

using geom::Vec3;

Patch patch_at(const FrameSurface& frame, const Vec3& at, double radius) {
  const auto closest = frame.tree.closest_point(at);
  auto patch = build_patch(frame, {closest.point, closest.triangle}, radius, 0, 0, 1, 0);
  update_weights(patch, radius);
  return patch;
}

/// Largest distance of the patch's vertices from where they started after `frames` frames over
/// [0, period] (the flow has reversed them home), projected on `frame` after every frame.
double return_error(const FrameSurface& frame, const VelocityField& flow, const Patch& start,
                    int frames, double period, int multiplier, double radius) {
  auto patch = start;
  AdvectionSettings settings{0.5 * frame.mean_edge_length, multiplier};
  for (int k = 1; k <= frames; ++k) {
    advect_patch(patch, flow, period * (k - 1) / frames, period * k / frames, settings);
    project_patch(patch, frame, radius);
  }
  EXPECT_EQ(patch.positions.size(), start.positions.size()) << "no vertex may be dropped";
  double error = 0;
  for (std::size_t v = 0; v < patch.positions.size(); ++v)
    error = std::max(error, (patch.positions[v] - start.positions[v]).norm());
  return error;
}

TEST(Advection, PlaneVortexReversesHomeAtFourthOrder) {
  const FrameSurface frame(geom::plane(Vec3(1, 1, 0), 40));
  AnalyticFlowSettings vortex;
  vortex.kind = FlowKind::plane_vortex;
  vortex.centre = Vec3(0.5, 0.5, 0);
  vortex.rate = 4.0;
  vortex.width = 0.2;
  vortex.period = 1.0;
  const auto flow = make_analytic_flow(vortex);
  const double r = 0.1;
  const auto start = patch_at(frame, Vec3(0.62, 0.5, 0), r);
  const double coarse = return_error(frame, *flow, start, 10, 1.0, 1, r);
  const double fine = return_error(frame, *flow, start, 10, 1.0, 2, r);
  EXPECT_LT(coarse, 1e-3 * r);
  EXPECT_GT(coarse, 8.0 * fine) << "coarse " << coarse << ", fine " << fine;
  // The flow did move the patch: half way, it is far from home.
  auto half = start;
  advect_patch(half, *flow, 0.0, 0.5, {0.5 * frame.mean_edge_length, 1});
  double moved = 0;
  for (std::size_t v = 0; v < half.positions.size(); ++v)
    moved = std::max(moved, (half.positions[v] - start.positions[v]).norm());
  EXPECT_GT(moved, r);
}

TEST(Advection, SphereShearReversesHomeWithinAFewPercentOfAnEdge) {
  const FrameSurface frame(geom::icosphere(4));
  AnalyticFlowSettings shear;
  shear.kind = FlowKind::sphere_shear;
  shear.rate = 2.0;
  shear.period = 1.0;
  const auto flow = make_analytic_flow(shear);
  const double r = 0.2;
  const auto start = patch_at(frame, Vec3(0.6, 0.2, 0.6).normalized(), r);
  EXPECT_LT(return_error(frame, *flow, start, 20, 1.0, 1, r), 0.05 * frame.mean_edge_length);
}

TEST(Advection, StrainErodesThePatchUntilEveryTexelGoes) {
  const FrameSurface frame(geom::plane(Vec3(4, 4, 0), 80));
  AnalyticFlowSettings strain;
  strain.kind = FlowKind::plane_strain;
  strain.centre = Vec3(2, 2, 0);
  strain.rate = 1.0;
  const auto flow = make_analytic_flow(strain);
  const double r = 0.3;
  auto patch = patch_at(frame, Vec3(2.01, 1.99, 0), r);
  const auto kept_area = [&] {
    double area = 0;
    for (const auto& t : patch.triangles) {
      std::array<Eigen::Vector2d, 3> rest;
      std::array<Vec3, 3> now;
      for (int c = 0; c < 3; ++c) {
        rest[std::size_t(c)] = patch.rest_uv[std::size_t(t[std::size_t(c)])] * 2 * r;
        now[std::size_t(c)] = patch.positions[std::size_t(t[std::size_t(c)])];
      }
      if (triangle_distortion(rest, now) < 3.0)
        area += 0.5 * (now[1] - now[0]).cross(now[2] - now[0]).norm();
    }
    return area;
  };
  double previous = kept_area();
  EXPECT_GT(previous, 0);
  const double dt = 0.1;
  int k = 0;
  for (; k < 40 && previous > 0; ++k) {
    advect_patch(patch, *flow, k * dt, (k + 1) * dt, {0.5 * frame.mean_edge_length, 1});
    project_patch(patch, frame, r);
    update_weights(patch, r);
    const double now = kept_area();
    // The strain keeps areas; RK4 keeps them to its truncation error.
    EXPECT_LE(now, previous * (1 + 1e-6)) << "frame " << k;
    previous = now;
  }
  ASSERT_EQ(previous, 0.0) << "still unstretched triangles after " << k << " frames";
  EXPECT_NEAR(k * dt, std::log(3.0), 0.3); // e^t reaches delta_max = 3
  const ErosionMask erosion(std::vector<float>(64, 1.0f), 8, 8, 0.1);
  for (const double w : patch.weights) {
    EXPECT_EQ(w, 0.0);
    for (const auto& uv : patch.rest_uv)
      EXPECT_TRUE(erosion.eroded(uv, w));
  }
}

TEST(GridVelocity, TrilinearInWorldSpaceAndLinearInTime) {
  // v(x) = A x + c on a grid with an origin and unequal spacing: trilinear is exact for it.
  vol::RgbGrid a(vol::Dims{5, 4, 3}), b(vol::Dims{5, 4, 3});
  for (auto* grid : {&a, &b}) {
    grid->set_origin({-1.0, 0.5, 2.0});
    grid->set_spacing({0.5, 0.25, 1.0});
  }
  const auto field = [](const Vec3& x, double scale) -> Vec3 {
    return scale * Vec3(x.x() + 2 * x.y(), -x.z(), 0.5 * x.x() + 1);
  };
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i) {
        const Vec3 x(-1.0 + 0.5 * i, 0.5 + 0.25 * j, 2.0 + k);
        const Vec3 va = field(x, 1.0), vb = field(x, 3.0);
        a.at(i, j, k) = {float(va.x()), float(va.y()), float(va.z())};
        b.at(i, j, k) = {float(vb.x()), float(vb.y()), float(vb.z())};
      }
  const auto velocity = make_grid_velocity(a, 1.0, b, 2.0);
  const Vec3 inside(0.3, 0.9, 3.4);
  EXPECT_LT((velocity->at(inside, 1.0) - field(inside, 1.0)).norm(), 1e-5);
  EXPECT_LT((velocity->at(inside, 2.0) - field(inside, 3.0)).norm(), 1e-5);
  EXPECT_LT((velocity->at(inside, 1.25) - field(inside, 1.5)).norm(), 1e-5);
  // Outside the grid: the border value (clamped), not an extrapolation.
  const Vec3 beyond(5.0, 0.9, 3.4), border(1.0, 0.9, 3.4);
  EXPECT_LT((velocity->at(beyond, 1.0) - field(border, 1.0)).norm(), 1e-5);
}

} // namespace
} // namespace texsim::pipelines::fluid_lapped
