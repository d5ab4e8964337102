#include "geom/aabb_tree.hpp"

#include "core/error.hpp"

#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <iterator>
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

/// Line parameter t where origin + t direction crosses the plane of triangle abc inside it
/// (edges included), or nullopt (outside, or parallel). Moller-Trumbore without culling.
std::optional<double> line_parameter(const Vec3& origin, const Vec3& direction, const Vec3& a,
                                     const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = direction.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) <= 1e-300)
    return std::nullopt;
  const Vec3 s = origin - a;
  const double u = s.dot(p) / det;
  const Vec3 q = s.cross(e1);
  const double v = direction.dot(q) / det;
  constexpr double kSlack = 1e-12; // points on an edge belong to both triangles
  if (u < -kSlack || v < -kSlack || u + v > 1 + kSlack)
    return std::nullopt;
  return e2.dot(q) / det;
}

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

std::optional<ClosestPoint> AabbTree::nearest_line_hit(const Vec3& origin,
                                                       const Vec3& direction) const {
  const Kernel::Line_3 line(to_cgal(origin), to_cgal(origin + direction));
  std::vector<Tree::Primitive_id> hits;
  impl_->tree.all_intersected_primitives(line, std::back_inserter(hits));
  std::optional<ClosestPoint> best;
  double best_t = std::numeric_limits<double>::infinity();
  for (const auto primitive : hits) {
    const auto& tri = *primitive;
    const auto corner = [&](int i) {
      const auto& p = tri.vertex(i);
      return Vec3(p.x(), p.y(), p.z());
    };
    const auto t = line_parameter(origin, direction, corner(0), corner(1), corner(2));
    if (!t)
      continue;
    const auto id = static_cast<std::int32_t>(primitive - impl_->triangles.cbegin());
    if (std::abs(*t) < best_t || (std::abs(*t) == best_t && id < best->triangle)) {
      best_t = std::abs(*t);
      best = ClosestPoint{origin + *t * direction, id, best_t * direction.norm()};
    }
  }
  return best;
}

} // namespace texsim::geom
