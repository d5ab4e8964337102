#include "pipelines/fluid_lapped/analytic_flows.hpp"

#include <cmath>

namespace texsim::pipelines::fluid_lapped {
namespace {

class AnalyticFlow : public VelocityField {
public:
  explicit AnalyticFlow(const AnalyticFlowSettings& settings) : s_(settings) {}

  geom::Vec3 at(const geom::Vec3& x, double time) const override {
    const double reversal = s_.period > 0 ? std::cos(M_PI * time / s_.period) : 1.0;
    const geom::Vec3 d = x - s_.centre;
    switch (s_.kind) {
    case FlowKind::zero:
      return geom::Vec3::Zero();
    case FlowKind::plane_vortex: {
      const double rho2 = d.x() * d.x() + d.y() * d.y();
      const double w = s_.rate * std::exp(-rho2 / (2.0 * s_.width * s_.width));
      return reversal * w * geom::Vec3(-d.y(), d.x(), 0.0);
    }
    case FlowKind::sphere_shear:
      return reversal * s_.rate * (x.z() / s_.sphere_radius) * geom::Vec3(-x.y(), x.x(), 0.0);
    case FlowKind::plane_strain:
      return reversal * s_.rate * geom::Vec3(d.x(), -d.y(), 0.0);
    }
    return geom::Vec3::Zero();
  }

private:
  AnalyticFlowSettings s_;
};

} // namespace

AnalyticFlowSettings read_analytic_flow(const ConfigSection& section) {
  AnalyticFlowSettings flow;
  flow.kind = section.choice<FlowKind>("kind", flow.kind,
                                       {{"zero", FlowKind::zero},
                                        {"plane_vortex", FlowKind::plane_vortex},
                                        {"sphere_shear", FlowKind::sphere_shear},
                                        {"plane_strain", FlowKind::plane_strain}});
  const auto centre = section.get<std::array<double, 3>>(
      "centre", {flow.centre.x(), flow.centre.y(), flow.centre.z()});
  flow.centre = geom::Vec3(centre[0], centre[1], centre[2]);
  flow.rate = section.get<double>("rate", flow.rate);
  flow.width = section.get<double>("width", flow.width, positive());
  flow.sphere_radius = section.get<double>("sphere_radius", flow.sphere_radius, positive());
  flow.period = section.get<double>("period", flow.period, non_negative());
  return flow;
}

std::unique_ptr<VelocityField> make_analytic_flow(const AnalyticFlowSettings& settings) {
  return std::make_unique<AnalyticFlow>(settings);
}

} // namespace texsim::pipelines::fluid_lapped
