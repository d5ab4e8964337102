#include "pipelines/fluid_lapped/patch_builder.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"
#include "geom/lscm_parameterization.hpp"
#include "geom/mesh_measures.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <set>

namespace texsim::pipelines::fluid_lapped {
namespace {

using geom::Vec3;

/// Distance from p to the closest point of triangle (a, b, c) (Ericson, Real-Time Collision
/// Detection 5.1.5: Voronoi regions of the corners, edges and face).
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0)
    return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3)
    return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
    return (p - (a + ab * (d1 / (d1 - d3)))).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6)
    return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
    return (p - (a + ac * (d2 / (d2 - d6)))).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
  const double denominator = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denominator) + ac * (vc * denominator))).norm();
}

/// The triangles of the patch: grown from p's triangle over edges, nearest first.
class DiskGrowth {
public:
  DiskGrowth(const FrameSurface& frame, const geom::SurfacePoint& centre, double radius)
      : frame_(frame), p_(centre.position),
        normal_(frame.triangle_normals[std::size_t(centre.triangle)]), radius_(radius) {
    add(centre.triangle);
    while (!queue_.empty()) {
      const auto [distance, t] = queue_.top();
      queue_.pop();
      if (!in_patch_.contains(t) && keeps_disk(t))
        add(t);
    }
  }

  const std::vector<std::int32_t>& triangles() const { return order_; }

private:
  using Candidate = std::pair<double, std::int32_t>; // (distance to p, triangle)

  /// The triangle across side `side` (opposite corner `side`) of t, or -1.
  std::int32_t across(std::int32_t t, int side) const {
    const auto edge = frame_.topology.triangle_edges(t)[std::size_t(side)];
    const auto around = frame_.topology.edge_triangles(edge);
    if (around.size() != 2)
      return -1;
    return around[0] == t ? around[1] : around[0];
  }

  bool touches(std::int32_t vertex) const {
    const auto around = frame_.topology.vertex_triangles().row(vertex);
    return std::any_of(around.begin(), around.end(),
                       [&](std::int32_t t) { return in_patch_.contains(t); });
  }

  bool keeps_disk(std::int32_t t) const {
    int shared = 0, shared_side = -1;
    for (int side = 0; side < 3; ++side)
      if (const auto other = across(t, side); other >= 0 && in_patch_.contains(other)) {
        ++shared;
        shared_side = side;
      }
    if (shared == 1) // the corner opposite the shared edge must be new, or the disk pinches
      return !touches(frame_.mesh.triangles[std::size_t(t)][std::size_t(shared_side)]);
    return shared == 2; // three shared edges would close a sphere
  }

  void add(std::int32_t t) {
    in_patch_.insert(t);
    order_.push_back(t);
    for (int side = 0; side < 3; ++side) {
      const auto other = across(t, side);
      if (other < 0 || in_patch_.contains(other) ||
          frame_.triangle_normals[std::size_t(other)].dot(normal_) <= 0)
        continue;
      const auto& tri = frame_.mesh.triangles[std::size_t(other)];
      const double distance = distance_to_triangle(p_, frame_.mesh.positions[std::size_t(tri[0])],
                                                   frame_.mesh.positions[std::size_t(tri[1])],
                                                   frame_.mesh.positions[std::size_t(tri[2])]);
      if (distance <= radius_)
        queue_.push({distance, other});
    }
  }

  const FrameSurface& frame_;
  Vec3 p_, normal_;
  double radius_;
  std::set<std::int32_t> in_patch_;
  std::vector<std::int32_t> order_;
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> queue_;
};

/// uv of a single triangle laid out isometrically.
std::vector<Eigen::Vector2d> isometric_layout(const geom::TriangleMesh& disk) {
  const Vec3 &a = disk.positions[0], &b = disk.positions[1], &c = disk.positions[2];
  const Vec3 e1 = (b - a).normalized();
  const Vec3 e2 = (b - a).cross(c - a).cross(b - a).normalized();
  return {Eigen::Vector2d::Zero(), Eigen::Vector2d((b - a).norm(), 0.0),
          Eigen::Vector2d(e1.dot(c - a), e2.dot(c - a))};
}

} // namespace

Patch build_patch(const FrameSurface& frame, const geom::SurfacePoint& centre, double radius,
                  std::int64_t id, std::int32_t frame_index, std::uint64_t seed,
                  std::uint64_t rotation_key) {
  TEXSIM_VERIFY(centre.triangle >= 0 && centre.triangle < frame.mesh.num_triangles(),
                "patch " << id << " centred on triangle " << centre.triangle
                         << " outside the frame");
  Patch patch;
  patch.id = id;
  patch.birth_frame = frame_index;
  geom::TriangleMesh disk;
  std::vector<std::int32_t> frame_vertex;
  std::vector<Eigen::Vector2d> uv;
  for (double grow_radius = radius;; grow_radius *= 0.75) {
    const DiskGrowth growth(frame, centre, grow_radius);
    disk = {};
    frame_vertex.clear();
    std::map<std::int32_t, std::int32_t> local;
    for (const auto t : growth.triangles()) {
      geom::Triangle corners{};
      for (int c = 0; c < 3; ++c) {
        const auto v = frame.mesh.triangles[std::size_t(t)][std::size_t(c)];
        const auto [at, added] = local.emplace(v, std::int32_t(frame_vertex.size()));
        if (added) {
          frame_vertex.push_back(v);
          disk.positions.push_back(frame.mesh.positions[std::size_t(v)]);
        }
        corners[std::size_t(c)] = at->second;
      }
      disk.triangles.push_back(corners);
    }
    if (disk.num_triangles() == 1) {
      uv = isometric_layout(disk);
      break;
    }
    try {
      uv = geom::lscm_parameterize(disk);
      break;
    } catch (const Error&) {
      // A patch LSCM cannot flatten: grow a smaller one.
    }
  }
  // Scale to the surface area, turn, put p at the centre, r -> 0.5.
  double uv_area = 0, surface_area = 0;
  for (const auto& t : disk.triangles) {
    const Eigen::Vector2d a = uv[std::size_t(t[1])] - uv[std::size_t(t[0])],
                          b = uv[std::size_t(t[2])] - uv[std::size_t(t[0])];
    uv_area += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    surface_area +=
        geom::triangle_area(disk.positions[std::size_t(t[0])], disk.positions[std::size_t(t[1])],
                            disk.positions[std::size_t(t[2])]);
  }
  const double scale = uv_area > 0 ? std::sqrt(surface_area / uv_area) : 1.0;
  const CounterRng rng(seed, kPatchRotationStream);
  const Eigen::Rotation2Dd turn(2.0 * M_PI * rng.uniform(rotation_key, 0));
  // p's uv from its triangle's corners (p's triangle is always the first patch triangle).
  const auto& first = disk.triangles.front();
  const auto weights = geom::barycentric_weights(
      disk.positions[std::size_t(first[0])], disk.positions[std::size_t(first[1])],
      disk.positions[std::size_t(first[2])], centre.position);
  Eigen::Vector2d uv_p = Eigen::Vector2d::Zero();
  for (int c = 0; c < 3; ++c)
    uv_p += weights[std::size_t(c)] * uv[std::size_t(first[std::size_t(c)])];
  const double to_uv = 0.5 / radius;
  for (std::size_t v = 0; v < uv.size(); ++v) {
    patch.rest_uv.push_back(Eigen::Vector2d(0.5, 0.5) + to_uv * scale * (turn * (uv[v] - uv_p)));
    // Where projection would put the vertex, so a still fluid leaves the patch unchanged.
    const auto on_surface = frame.tree.closest_point(disk.positions[v]);
    patch.positions.push_back(on_surface.point);
    patch.surface_triangle.push_back(on_surface.triangle);
  }
  patch.triangles = std::move(disk.triangles);
  patch.weights.assign(patch.positions.size(), 0.0);
  return patch;
}

std::uint64_t created_patch_rotation_key(std::int32_t frame_index, int x, int y) {
  // 24 bits of x and y each (atlases up to 16M texels a side), the frame + 1 above them.
  return (std::uint64_t(frame_index + 1) << 48) | (std::uint64_t(y) << 24) | std::uint64_t(x);
}

} // namespace texsim::pipelines::fluid_lapped
