#include "pipelines/fem_rd/pattern_orientation.hpp"

#include "par/reproducible_sum.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <vector>

namespace texsim::pipelines::fem_rd {

StripeOrientation stripe_orientation(const geom::DistributedMesh& mesh,
                                     std::span<const double> values, const DiffusionField& field) {
  const auto& surface = mesh.mesh();
  field.update_mesh_fields(surface);
  const auto directions = field.tangent_directions(surface);
  std::vector<double> tt, tb, bb; // structure tensor entries of each owned triangle
  for (const std::int32_t t : mesh.owned_triangles()) {
    const auto& tri = surface.triangles[std::size_t(t)];
    const geom::Vec3 &p0 = surface.positions[tri[0]], &p1 = surface.positions[tri[1]],
                     &p2 = surface.positions[tri[2]];
    const geom::Vec3 doubled_normal = (p1 - p0).cross(p2 - p0);
    const double doubled_area = doubled_normal.norm();
    if (!(doubled_area > 0))
      continue;
    const geom::Vec3 n = doubled_normal / doubled_area;
    geom::Vec3 along = directions[tri[0]] + directions[tri[1]] + directions[tri[2]];
    along -= along.dot(n) * n;
    if (!(along.norm() > 0))
      continue;
    along.normalize();
    const geom::Vec3 across = n.cross(along);
    // The P1 gradient: sum over corners of u_i (n x opposite edge) / (2 area).
    geom::Vec3 gradient = geom::Vec3::Zero();
    for (int c = 0; c < 3; ++c) {
      const geom::Vec3 edge =
          surface.positions[tri[(c + 2) % 3]] - surface.positions[tri[(c + 1) % 3]];
      gradient += values[std::size_t(tri[c])] * n.cross(edge);
    }
    gradient /= doubled_area;
    const double a = gradient.dot(along), b = gradient.dot(across), weight = 0.5 * doubled_area;
    tt.push_back(weight * a * a);
    tb.push_back(weight * a * b);
    bb.push_back(weight * b * b);
  }
  const double jtt = par::reproducible_sum(mesh.comm(), tt);
  const double jtb = par::reproducible_sum(mesh.comm(), tb);
  const double jbb = par::reproducible_sum(mesh.comm(), bb);
  // The dominant gradient direction, from the field's direction; the stripes run 90 degrees off.
  const double gradient_angle = 0.5 * std::atan2(2 * jtb, jtt - jbb) * 180 / std::numbers::pi;
  const double stripes = 90 - std::fabs(gradient_angle);
  const double spread = std::hypot(jtt - jbb, 2 * jtb), trace = jtt + jbb;
  return {stripes, trace > 0 ? spread / trace : 0.0};
}

} // namespace texsim::pipelines::fem_rd
