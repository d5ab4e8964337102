#include "geom/poisson_disk_points.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"
#include "geom/random_surface_points.hpp"

#include <cmath>
#include <unordered_map>

namespace texsim::geom {
namespace {

/// Accepted points in a uniform grid of cells of side `radius`, for "is any point closer than
/// radius" queries over the 27 cells around a query.
class DiskGrid {
public:
  explicit DiskGrid(double radius) : radius_(radius) {}

  bool has_point_within_radius(const Vec3& p) const {
    const auto c = cell(p);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto found = cells_.find(key(c[0] + dx, c[1] + dy, c[2] + dz));
          if (found == cells_.end())
            continue;
          for (const auto& q : found->second)
            if ((q - p).squaredNorm() <= radius_ * radius_)
              return true;
        }
    return false;
  }

  void add(const Vec3& p) {
    const auto c = cell(p);
    cells_[key(c[0], c[1], c[2])].push_back(p);
  }

private:
  std::array<std::int64_t, 3> cell(const Vec3& p) const {
    return {std::int64_t(std::floor(p.x() / radius_)), std::int64_t(std::floor(p.y() / radius_)),
            std::int64_t(std::floor(p.z() / radius_))};
  }
  static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    // 21 bits per axis: cells far apart may share a key, which only costs distance checks.
    const auto bits = [](std::int64_t v) { return std::uint64_t(v) & ((1u << 21) - 1); };
    return bits(x) | (bits(y) << 21) | (bits(z) << 42);
  }

  double radius_;
  std::unordered_map<std::uint64_t, std::vector<Vec3>> cells_;
};

} // namespace

std::vector<SurfacePoint> poisson_disk_points(const TriangleMesh& mesh, double radius,
                                              std::uint64_t seed) {
  TEXSIM_VERIFY(radius > 0, "poisson_disk_points needs a positive radius, got " << radius);
  const AreaSampler sampler(mesh);
  const CounterRng rng(seed, kPoissonDiskStream);
  DiskGrid grid(radius);
  std::vector<SurfacePoint> points;
  const auto offer = [&](const SurfacePoint& candidate) {
    if (grid.has_point_within_radius(candidate.position))
      return;
    grid.add(candidate.position);
    points.push_back(candidate);
  };
  const double darts = std::ceil(30.0 * sampler.total_area() / (radius * radius));
  TEXSIM_VERIFY(darts < 1e9, "poisson_disk_points: radius " << radius << " is too small for a "
                                                            << "surface of area "
                                                            << sampler.total_area());
  for (std::uint64_t id = 0; id < std::uint64_t(darts); ++id)
    offer(sampler.sample(rng, id));
  // Fill: every triangle's barycentric grid, fine enough that the gaps dart throwing left close.
  const double spacing = radius / 8.0;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& tri = mesh.triangles[std::size_t(t)];
    const Vec3 &a = mesh.positions[std::size_t(tri[0])], &b = mesh.positions[std::size_t(tri[1])],
               &c = mesh.positions[std::size_t(tri[2])];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, int(std::ceil(longest / spacing)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = double(i) / n, v = double(j) / n;
        offer({a + u * (b - a) + v * (c - a), t});
      }
  }
  return points;
}

} // namespace texsim::geom
