#include "par/morton_partition.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <numeric>

namespace texsim::par {
namespace {
// Spreads the low 21 bits of x so that two zero bits separate each pair.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}
} // namespace

std::uint64_t morton_key(const std::array<double, 3>& p, const std::array<double, 3>& lo,
                         const std::array<double, 3>& hi) {
  constexpr double kCells = double((1 << 21) - 1);
  std::uint64_t key = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double extent = hi[axis] - lo[axis];
    const double t = extent > 0 ? std::clamp((p[axis] - lo[axis]) / extent, 0.0, 1.0) : 0.0;
    key |= spread_bits(static_cast<std::uint64_t>(t * kCells)) << axis;
  }
  return key;
}

std::vector<std::uint64_t> morton_keys(const std::vector<std::array<double, 3>>& points) {
  std::array<double, 3> lo{}, hi{};
  if (!points.empty()) {
    lo = hi = points.front();
    for (const auto& p : points)
      for (int axis = 0; axis < 3; ++axis) {
        lo[axis] = std::min(lo[axis], p[axis]);
        hi[axis] = std::max(hi[axis], p[axis]);
      }
  }
  std::vector<std::uint64_t> keys(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    keys[i] = morton_key(points[i], lo, hi);
  return keys;
}

std::vector<int> morton_partition(const std::vector<std::array<double, 3>>& points, int parts) {
  TEXSIM_VERIFY(parts > 0, "morton_partition: parts must be positive, got " << parts);
  const auto keys = morton_keys(points);
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return keys[a] != keys[b] ? keys[a] < keys[b] : a < b;
  });
  std::vector<int> part(points.size());
  const std::size_t n = points.size();
  for (std::size_t rank_in_order = 0; rank_in_order < n; ++rank_in_order)
    part[order[rank_in_order]] = static_cast<int>(rank_in_order * parts / n);
  return part;
}

} // namespace texsim::par
