#pragma once
/// Values given at the vertices of one surface, read at points of another surface close to it
/// (a refined, scaled or noisy copy, or points placed on it): the piecewise-linear interpolant at
/// the closest point. How a per-vertex field of an input mesh reaches the cells of a retiling.
#include "geom/aabb_tree.hpp"
#include "geom/triangle_mesh.hpp"

#include <array>
#include <span>
#include <vector>

namespace texsim::geom {

class SurfaceFieldSampler {
public:
  /// `values[k]` holds field k at every vertex of `mesh`. Serial.
  SurfaceFieldSampler(const TriangleMesh& mesh, std::vector<std::vector<double>> values);

  std::size_t field_count() const { return values_.size(); }

  /// Field `k` at each point: the closest point of the mesh, then the barycentric combination of
  /// its triangle's vertex values. Exact for fields linear over each triangle. Not collective;
  /// thread-safe.
  std::vector<double> sample(std::size_t k, std::span<const Vec3> points) const;

  /// Every field at each point from one closest-point query per point, and the largest distance
  /// from a point to the surface. Not collective.
  struct Sampled {
    std::vector<std::vector<double>> values; ///< [field][point]
    double max_distance = 0;
  };
  Sampled sample_all(std::span<const Vec3> points) const;

private:
  /// A point's closest point: its triangle's corners, barycentric weights and distance.
  struct Location {
    Triangle corners;
    std::array<double, 3> weights;
    double distance;
  };
  Location locate(const Vec3& point) const;
  double interpolate(const Location& at, std::size_t k) const;

  TriangleMesh mesh_;
  std::vector<std::vector<double>> values_;
  AabbTree tree_;
};

} // namespace texsim::geom
