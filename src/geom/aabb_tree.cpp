#include "geom/aabb_tree.hpp"

#include "core/error.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
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

} // namespace texsim::geom
