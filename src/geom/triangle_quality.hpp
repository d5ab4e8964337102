#pragma once
/// Shape quality of a mesh's triangles, as FEM sees it: the smallest angle and the aspect ratio
/// (slivers and needles make the P1 stiffness matrix badly conditioned). Serial.
#include "geom/triangle_mesh.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <string>

namespace texsim::geom {

struct TriangleQuality {
  /// Upper ends of the aspect-ratio bins; the last bin holds everything above the last bound.
  static constexpr std::array<double, 6> kAspectBounds{1.5, 2, 3, 5, 10, 100};

  double min_angle_deg = 0;      ///< smallest corner angle of any triangle
  double mean_min_angle_deg = 0; ///< mean over triangles of their smallest angle
  double max_aspect_ratio = 0;
  /// Triangles per aspect-ratio bin: [1, 1.5), [1.5, 2), [2, 3), [3, 5), [5, 10), [10, 100),
  /// [100, inf); a triangle of zero area counts in the last bin.
  std::array<std::size_t, kAspectBounds.size() + 1> aspect_histogram{};

  /// {"min_angle_deg", "mean_min_angle_deg", "max_aspect_ratio", "aspect_ratio_histogram":
  /// {"[1,1.5)": n, ...}} for summary.json.
  nlohmann::json metrics() const;
  /// One line for the log.
  std::string summary() const;
};

/// Aspect ratio of triangle (a, b, c): longest edge / (2 sqrt(3) inradius), 1 for an equilateral
/// triangle, growing without bound for slivers and needles; infinite for zero area.
double aspect_ratio(const Vec3& a, const Vec3& b, const Vec3& c);

/// Smallest angle, aspect ratios and their histogram over every triangle of `mesh`.
TriangleQuality triangle_quality(const TriangleMesh& mesh);

} // namespace texsim::geom
