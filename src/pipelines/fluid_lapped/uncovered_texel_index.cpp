#include "pipelines/fluid_lapped/uncovered_texel_index.hpp"

#include "core/error.hpp"

namespace texsim::pipelines::fluid_lapped {

UncoveredTexelIndex::UncoveredTexelIndex(std::span<const UncoveredTexel> texels) : texels_(texels) {
  if (texels.empty())
    return;
  extent_ = {texels.front().x, texels.front().y, texels.front().x + 1, texels.front().y + 1};
  blocks_.reserve(texels.size());
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const auto& texel = texels[i];
    TEXSIM_VERIFY(texel.x >= 0 && texel.y >= 0, "uncovered texel outside the atlas");
    extent_ = {std::min(extent_.x0, texel.x), std::min(extent_.y0, texel.y),
               std::max(extent_.x1, texel.x + 1), std::max(extent_.y1, texel.y + 1)};
    blocks_.emplace_back(block_key(texel.x / kBlock, texel.y / kBlock), std::int32_t(i));
  }
  std::sort(blocks_.begin(), blocks_.end());
}

} // namespace texsim::pipelines::fluid_lapped
