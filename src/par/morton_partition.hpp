#pragma once
/// Space-filling-curve partition of points: sorted along a 3D Morton (Z-order) curve and cut into
/// contiguous runs of equal count, so each part is spatially compact and parts differ by at most
/// one point. Deterministic: the same points give the same parts on any number of ranks.
#include <array>
#include <cstdint>
#include <vector>

namespace texsim::par {

/// The 63-bit Morton key of p inside the box [lo, hi] (21 bits per axis).
std::uint64_t morton_key(const std::array<double, 3>& p, const std::array<double, 3>& lo,
                         const std::array<double, 3>& hi);

/// The Morton key of every point inside the points' bounding box.
std::vector<std::uint64_t> morton_keys(const std::vector<std::array<double, 3>>& points);

/// part[i] in [0, parts) for each point i. Ties in the key are broken by index.
std::vector<int> morton_partition(const std::vector<std::array<double, 3>>& points, int parts);

} // namespace texsim::par
