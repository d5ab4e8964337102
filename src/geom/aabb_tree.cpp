#include "geom/aabb_tree.hpp"

#include "core/error.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace texsim::geom {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 to_cgal(const Vec3& p) {
  return {p.x(), p.y(), p.z()};
}

Vec3 from_cgal(const Kernel::Point_3& p) {
  return {p.x(), p.y(), p.z()};
}

/// Barycentric slack of a line hit: points on a shared edge belong to both triangles.
constexpr double kHitSlack = 1e-12;
/// Sine of the angle between line and triangle below which they count as parallel.
constexpr double kParallelSine = 1e-12;
/// Node boxes are grown by this fraction of their largest coordinate, so round-off in the box
/// test never drops a triangle the hit or distance test accepts.
constexpr double kBoxPadding = 1e-9;

/// A node's box grown by kBoxPadding.
struct PaddedBox {
  explicit PaddedBox(const CGAL::Bbox_3& box) {
    double scale = 0.0;
    for (int axis = 0; axis < 3; ++axis)
      scale = std::max({scale, std::abs(box.min(axis)), std::abs(box.max(axis))});
    const double pad = kBoxPadding * scale + std::numeric_limits<double>::min();
    for (int axis = 0; axis < 3; ++axis) {
      lo[axis] = box.min(axis) - pad;
      hi[axis] = box.max(axis) + pad;
    }
  }
  double lo[3], hi[3];
};

/// The line parameter where origin + t direction crosses triangle abc (Moller-Trumbore, both
/// sides), or nullopt when it passes outside or runs parallel.
std::optional<double> line_crossing(const Vec3& origin, const Vec3& direction, const Vec3& a,
                                    const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = direction.cross(e2);
  const double det = e1.dot(p); // -direction . (e1 x e2)
  if (std::abs(det) <= kParallelSine * direction.norm() * e1.cross(e2).norm())
    return std::nullopt;
  const Vec3 s = origin - a;
  const double u = s.dot(p) / det;
  const Vec3 q = s.cross(e1);
  const double v = direction.dot(q) / det;
  if (u < -kHitSlack || v < -kHitSlack || u + v > 1.0 + kHitSlack)
    return std::nullopt;
  return e2.dot(q) / det;
}

struct Line {
  Vec3 origin, direction;
};

/// CGAL traversal traits: visits the boxes the line crosses no farther from the origin than the
/// best hit so far and keeps the hit of smallest (|t|, triangle id).
class NearestLineHit {
public:
  explicit NearestLineHit(Triangles::const_iterator first) : first_(first) {}

  bool go_further() const { return true; }

  template <class Primitive> void intersection(const Line& line, const Primitive& primitive) {
    const Kernel::Triangle_3& tri = primitive.datum();
    const auto t = line_crossing(line.origin, line.direction, from_cgal(tri.vertex(0)),
                                 from_cgal(tri.vertex(1)), from_cgal(tri.vertex(2)));
    if (!t)
      return;
    const auto id = static_cast<std::int32_t>(primitive.id() - first_);
    const double abs_t = std::abs(*t);
    if (abs_t < best_abs_t_ || (abs_t == best_abs_t_ && id < best_id_)) {
      best_abs_t_ = abs_t;
      best_t_ = *t;
      best_id_ = id;
    }
  }

  template <class Node> bool do_intersect(const Line& line, const Node& node) const {
    const PaddedBox box(node.bbox());
    double t_lo = -std::numeric_limits<double>::infinity();
    double t_hi = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
      const double lo = box.lo[axis], hi = box.hi[axis];
      const double o = line.origin[axis], d = line.direction[axis];
      if (d == 0.0) {
        if (o < lo || o > hi)
          return false;
        continue;
      }
      const double enter = (lo - o) / d, leave = (hi - o) / d;
      t_lo = std::max(t_lo, std::min(enter, leave));
      t_hi = std::min(t_hi, std::max(enter, leave));
      if (t_lo > t_hi)
        return false;
    }
    const double nearest =
        t_lo <= 0.0 && t_hi >= 0.0 ? 0.0 : std::min(std::abs(t_lo), std::abs(t_hi));
    return nearest <= best_abs_t_;
  }

  std::optional<LineCrossing> result() const {
    if (best_id_ < 0)
      return std::nullopt;
    return LineCrossing{best_id_, best_t_};
  }

private:
  Triangles::const_iterator first_;
  double best_abs_t_ = std::numeric_limits<double>::infinity();
  double best_t_ = 0.0;
  std::int32_t best_id_ = -1;
};

/// CGAL traversal traits: visits the boxes no farther from the query than the best triangle so
/// far (ties included) and keeps the triangle of smallest (squared distance, id).
class LowestIdNearest {
public:
  LowestIdNearest(Triangles::const_iterator first, NearestTriangle start)
      : first_(first), best_(start) {}

  bool go_further() const { return true; }

  template <class Primitive> void intersection(const Vec3& query, const Primitive& primitive) {
    const auto id = static_cast<std::int32_t>(primitive.id() - first_);
    const auto candidate = nearest_on(primitive.datum(), id, query);
    if (candidate.squared_distance < best_.squared_distance ||
        (candidate.squared_distance == best_.squared_distance && id < best_.triangle))
      best_ = candidate;
  }

  template <class Node> bool do_intersect(const Vec3& query, const Node& node) const {
    const PaddedBox box(node.bbox());
    double squared = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      const double below = box.lo[axis] - query[axis];
      const double above = query[axis] - box.hi[axis];
      const double gap = std::max({below, above, 0.0});
      squared += gap * gap;
    }
    return squared <= best_.squared_distance;
  }

  static NearestTriangle nearest_on(const Kernel::Triangle_3& triangle, std::int32_t id,
                                    const Vec3& query) {
    const Kernel kernel;
    const auto q = to_cgal(query);
    const auto projected = kernel.construct_projected_point_3_object()(triangle, q);
    return {from_cgal(projected), id, kernel.compute_squared_distance_3_object()(q, projected)};
  }

  const NearestTriangle& result() const { return best_; }

private:
  Triangles::const_iterator first_;
  NearestTriangle best_;
};

} // namespace

struct AabbTree::Impl {
  Triangles triangles;
  Tree tree;
};

AabbTree::AabbTree(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  TEXSIM_VERIFY(!mesh.triangles.empty(), "AabbTree: mesh has no triangles");
  impl_->triangles.reserve(mesh.triangles.size());
  for (const auto& tri : mesh.triangles) {
    impl_->triangles.emplace_back(to_cgal(mesh.positions[tri[0]]), to_cgal(mesh.positions[tri[1]]),
                                  to_cgal(mesh.positions[tri[2]]));
  }
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

AabbTree::~AabbTree() = default;
AabbTree::AabbTree(AabbTree&&) noexcept = default;
AabbTree& AabbTree::operator=(AabbTree&&) noexcept = default;

ClosestPoint AabbTree::closest_point(const Vec3& query) const {
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(to_cgal(query));
  const Vec3 p(point.x(), point.y(), point.z());
  return {p, static_cast<std::int32_t>(primitive - impl_->triangles.cbegin()), (p - query).norm()};
}

NearestTriangle AabbTree::nearest_triangle(const Vec3& query) const {
  // CGAL's answer bounds the search; the second pass visits only boxes within that bound and
  // settles ties by id.
  const auto start = impl_->tree.closest_point_and_primitive(to_cgal(query)).second;
  const auto start_id = static_cast<std::int32_t>(start - impl_->triangles.cbegin());
  LowestIdNearest traits(impl_->triangles.cbegin(),
                         LowestIdNearest::nearest_on(*start, start_id, query));
  impl_->tree.traversal(query, traits);
  return traits.result();
}

std::optional<ClosestPoint> AabbTree::nearest_line_hit(const Vec3& origin,
                                                       const Vec3& direction) const {
  const auto crossing = nearest_line_crossing(origin, direction);
  if (!crossing)
    return std::nullopt;
  return ClosestPoint{origin + crossing->t * direction, crossing->triangle,
                      std::abs(crossing->t) * direction.norm()};
}

std::optional<LineCrossing> AabbTree::nearest_line_crossing(const Vec3& origin,
                                                            const Vec3& direction) const {
  if (direction == Vec3::Zero())
    return std::nullopt;
  const Line line{origin, direction};
  NearestLineHit traits(impl_->triangles.cbegin());
  impl_->tree.traversal(line, traits);
  return traits.result();
}

} // namespace texsim::geom
