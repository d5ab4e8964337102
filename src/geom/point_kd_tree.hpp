#pragma once
/// A nanoflann kd-tree over points held elsewhere: the seeds of restricted_voronoi's neighbour
/// queries and of restricted_delaunay's meeting test.
#include "geom/triangle_mesh.hpp"

#include <nanoflann.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace texsim::geom {

/// nanoflann's view of the points (they must outlive the tree).
struct PointCloudView {
  std::span<const Vec3> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::uint32_t i, std::size_t d) const { return points[i][d]; }
  template <class Box> bool kdtree_get_bbox(Box&) const { return false; }
};

/// Built by its constructor: PointKdTree tree(3, view,
/// nanoflann::KDTreeSingleIndexAdaptorParams(12)).
using PointKdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, PointCloudView, double, std::uint32_t>, PointCloudView, 3,
    std::uint32_t>;

} // namespace texsim::geom
