#pragma once
/// Velocity fields given by formulas, for CI and the tests (the "analytic flows"). Each
/// is multiplied by cos(pi t / T) when a period T is set: the flow slows, reverses at T / 2 and
/// at t = T has carried every point back to where it started (time reversal), so advection
/// errors can be measured against the start.
#include "core/config.hpp"
#include "pipelines/fluid_lapped/velocity_field.hpp"

#include <memory>

namespace texsim::pipelines::fluid_lapped {

enum class FlowKind {
  zero,         ///< a still fluid
  plane_vortex, ///< v = w exp(-rho^2 / (2 width^2)) (-(y - cy), x - cx, 0): a shearing vortex
  sphere_shear, ///< v = w (z / R) (-y, x, 0): zonal shear on a sphere about z, tangent to it
  plane_strain, ///< v = w (x - cx, -(y - cy), 0): stretches along x, squeezes along y
};

struct AnalyticFlowSettings {
  FlowKind kind = FlowKind::plane_vortex; ///< kind
  geom::Vec3 centre{0.5, 0.5, 0.0};       ///< centre: of the vortex and the strain
  double rate = 1.0;   ///< rate: angular speed (vortex centre, sphere pole) or strain rate, 1/time
  double width = 0.25; ///< width: Gaussian core of the vortex, model units
  double sphere_radius = 1.0; ///< sphere_radius: R of the shear
  double period = 0.0;        ///< period: T of the reversal factor cos(pi t / T); 0: steady
};

/// Reads the `flow` section. Throws InputError naming the key.
AnalyticFlowSettings read_analytic_flow(const ConfigSection& section);

std::unique_ptr<VelocityField> make_analytic_flow(const AnalyticFlowSettings& settings);

} // namespace texsim::pipelines::fluid_lapped
