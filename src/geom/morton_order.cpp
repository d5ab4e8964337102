#include "geom/morton_order.hpp"

#include "core/error.hpp"
#include "par/distributed_sort.hpp"
#include "par/morton_partition.hpp"

#include <algorithm>
#include <array>
#include <numeric>
#include <tuple>

namespace texsim::geom {

DistributedSurfacePoints sort_along_morton_curve(const par::Comm& comm, const Box3& box,
                                                 DistributedSurfacePoints points) {
  TEXSIM_VERIFY(points.ids.size() == points.points.size(),
                "sort_along_morton_curve: " << points.ids.size() << " ids for "
                                            << points.points.size() << " points");
  struct Keyed {
    std::uint64_t key;
    std::int64_t id;
    double xyz[3];
    std::int32_t triangle;
  };
  const std::array<double, 3> lo{box.lo.x(), box.lo.y(), box.lo.z()};
  const std::array<double, 3> hi{box.hi.x(), box.hi.y(), box.hi.z()};
  std::vector<Keyed> keyed;
  keyed.reserve(points.ids.size());
  for (std::size_t i = 0; i < points.ids.size(); ++i) {
    const Vec3& p = points.points[i].position;
    keyed.push_back({par::morton_key({p.x(), p.y(), p.z()}, lo, hi),
                     points.ids[i],
                     {p.x(), p.y(), p.z()},
                     points.points[i].triangle});
  }
  points = {};
  const auto run =
      par::distributed_sort(comm, std::move(keyed), [](const Keyed& a, const Keyed& b) {
        return std::tie(a.key, a.id) < std::tie(b.key, b.id);
      });
  DistributedSurfacePoints sorted;
  sorted.ids.reserve(run.size());
  sorted.points.reserve(run.size());
  for (const auto& k : run) {
    sorted.ids.push_back(k.id);
    sorted.points.push_back({Vec3(k.xyz[0], k.xyz[1], k.xyz[2]), k.triangle});
  }
  return sorted;
}

namespace {
std::vector<std::array<double, 3>> triangle_centroids(const TriangleMesh& mesh) {
  std::vector<std::array<double, 3>> centroids(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 c = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3.0;
    centroids[t] = {c.x(), c.y(), c.z()};
  }
  return centroids;
}
} // namespace

std::vector<std::size_t> morton_triangle_order(const TriangleMesh& mesh) {
  const auto keys = par::morton_keys(triangle_centroids(mesh));
  std::vector<std::size_t> order(keys.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return keys[a] != keys[b] ? keys[a] < keys[b] : a < b;
  });
  return order;
}

std::vector<int> morton_triangle_parts(const TriangleMesh& mesh, int parts) {
  return par::morton_partition(triangle_centroids(mesh), parts);
}

} // namespace texsim::geom
