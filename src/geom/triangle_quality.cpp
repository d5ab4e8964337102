#include "geom/triangle_quality.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace texsim::geom {
namespace {

/// Angle at corner a of triangle (a, b, c), in degrees.
double corner_angle_deg(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = b - a, v = c - a;
  return std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / std::numbers::pi;
}

std::string bin_name(std::size_t bin) {
  const auto& bounds = TriangleQuality::kAspectBounds;
  std::ostringstream name;
  name << "[" << (bin == 0 ? 1.0 : bounds[bin - 1]) << ",";
  if (bin < bounds.size())
    name << bounds[bin] << ")";
  else
    name << "inf)";
  return name.str();
}

} // namespace

double aspect_ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
  const double twice_area = (b - a).cross(c - a).norm();
  if (!(twice_area > 0))
    return std::numeric_limits<double>::infinity();
  const double inradius = twice_area / (ab + bc + ca);
  return std::max({ab, bc, ca}) / (2.0 * std::sqrt(3.0) * inradius);
}

TriangleQuality triangle_quality(const TriangleMesh& mesh) {
  TriangleQuality quality;
  quality.min_angle_deg = 180.0;
  double min_angle_sum = 0;
  for (const auto& tri : mesh.triangles) {
    const Vec3& a = mesh.positions[tri[0]];
    const Vec3& b = mesh.positions[tri[1]];
    const Vec3& c = mesh.positions[tri[2]];
    const double smallest =
        std::min({corner_angle_deg(a, b, c), corner_angle_deg(b, c, a), corner_angle_deg(c, a, b)});
    quality.min_angle_deg = std::min(quality.min_angle_deg, smallest);
    min_angle_sum += smallest;
    const double aspect = aspect_ratio(a, b, c);
    quality.max_aspect_ratio = std::max(quality.max_aspect_ratio, aspect);
    const auto& bounds = TriangleQuality::kAspectBounds;
    const auto bin =
        std::size_t(std::upper_bound(bounds.begin(), bounds.end(), aspect) - bounds.begin());
    ++quality.aspect_histogram[bin];
  }
  if (!mesh.triangles.empty())
    quality.mean_min_angle_deg = min_angle_sum / double(mesh.triangles.size());
  else
    quality.min_angle_deg = 0;
  return quality;
}

nlohmann::json TriangleQuality::metrics() const {
  nlohmann::json histogram = nlohmann::json::object();
  for (std::size_t bin = 0; bin < aspect_histogram.size(); ++bin)
    histogram[bin_name(bin)] = aspect_histogram[bin];
  // JSON has no infinity: a zero-area triangle's aspect ratio is reported as null.
  const nlohmann::json max_aspect =
      std::isfinite(max_aspect_ratio) ? nlohmann::json(max_aspect_ratio) : nlohmann::json();
  return {{"min_angle_deg", min_angle_deg},
          {"mean_min_angle_deg", mean_min_angle_deg},
          {"max_aspect_ratio", max_aspect},
          {"aspect_ratio_histogram", histogram}};
}

std::string TriangleQuality::summary() const {
  std::ostringstream out;
  out << "smallest angle " << min_angle_deg << " deg (mean per triangle " << mean_min_angle_deg
      << "), largest aspect ratio " << max_aspect_ratio << "; aspect ratios";
  for (std::size_t bin = 0; bin < aspect_histogram.size(); ++bin)
    out << " " << bin_name(bin) << ": " << aspect_histogram[bin];
  return out.str();
}

} // namespace texsim::geom
