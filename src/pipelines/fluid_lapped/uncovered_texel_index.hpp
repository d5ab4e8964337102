#pragma once
/// The uncovered texels one round of patch creation walks, found by position. A drawn patch
/// triangle asks which of them lie in its sampling box; the texels are bucketed by square blocks
/// of the atlas, so that costs the texels near the box, not the whole list.
#include "geom/surface_point.hpp"
#include "geom/texture_atlas.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace texsim::pipelines::fluid_lapped {

/// A used texel that no patch covers, its chart, the surface point it shows, and that point's
/// image in the atlas (the texel centre, or for a gutter texel the nearest point of its chart).
struct UncoveredTexel {
  int x = 0, y = 0;
  std::int32_t chart = -1;
  geom::SurfacePoint point;
  std::array<float, 2> image{};
};

class UncoveredTexelIndex {
public:
  /// `texels` must outlive the index.
  explicit UncoveredTexelIndex(std::span<const UncoveredTexel> texels);

  std::span<const UncoveredTexel> texels() const { return texels_; }

  /// Calls visit(i) for every i with texels()[i] in [box.x0, box.x1) x [box.y0, box.y1).
  template <typename Visit> void for_each_inside(const geom::TexelRect& box, Visit&& visit) const {
    const geom::TexelRect clipped{std::max(box.x0, extent_.x0), std::max(box.y0, extent_.y0),
                                  std::min(box.x1, extent_.x1), std::min(box.y1, extent_.y1)};
    if (clipped.x0 >= clipped.x1 || clipped.y0 >= clipped.y1)
      return;
    for (int by = clipped.y0 / kBlock; by <= (clipped.y1 - 1) / kBlock; ++by)
      for (int bx = clipped.x0 / kBlock; bx <= (clipped.x1 - 1) / kBlock; ++bx) {
        const auto [first, last] =
            std::equal_range(blocks_.begin(), blocks_.end(), std::pair(block_key(bx, by), 0),
                             [](const auto& a, const auto& b) { return a.first < b.first; });
        for (auto at = first; at != last; ++at) {
          const auto& texel = texels_[std::size_t(at->second)];
          if (texel.x >= clipped.x0 && texel.x < clipped.x1 && texel.y >= clipped.y0 &&
              texel.y < clipped.y1)
            visit(at->second);
        }
      }
  }

private:
  static constexpr int kBlock = 16;
  static std::int64_t block_key(int bx, int by) { return (std::int64_t(by) << 32) | bx; }

  std::span<const UncoveredTexel> texels_;
  geom::TexelRect extent_; ///< the texels' bounding box
  /// (block key, position in texels_), sorted by key
  std::vector<std::pair<std::int64_t, std::int32_t>> blocks_;
};

} // namespace texsim::pipelines::fluid_lapped
