#include "pipelines/solid_synthesis/feature_kd_tree.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr int kLanes = kScanLanes;
/// Deeper than any tree over 2^31 voxels (median splits halve the lane blocks).
constexpr int kMaxDepth = 40;

} // namespace

FeatureKdTree::FeatureKdTree(const vol::ChannelGrid& features)
    : channels_(features.channels()), float_bound_(features.channels()) {
  const auto voxel_count = static_cast<std::int64_t>(features.voxel_count());
  TEXSIM_VERIFY(channels_ >= 1 && voxel_count > 0 &&
                    voxel_count <= std::numeric_limits<std::int32_t>::max(),
                "feature kd-tree: " << voxel_count << " voxels of " << channels_
                                    << " channels cannot be indexed");
  const std::int64_t chunks = (voxel_count + kLanes - 1) / kLanes;
  lane_blocks_.assign(static_cast<std::size_t>(chunks * kLanes * channels_),
                      std::numeric_limits<float>::infinity()); // padding lanes never hit
  voxels_.assign(static_cast<std::size_t>(chunks * kLanes), -1);
  std::vector<std::int32_t> order(static_cast<std::size_t>(voxel_count));
  for (std::size_t v = 0; v < order.size(); ++v)
    order[v] = static_cast<std::int32_t>(v);
  nodes_.reserve(static_cast<std::size_t>(2 * chunks));
  nodes_.emplace_back();
  boxes_.resize(static_cast<std::size_t>(2 * channels_));
  build_node(0, features, order, 0, chunks, 0);
}

void FeatureKdTree::build_node(std::int32_t node, const vol::ChannelGrid& features,
                               std::vector<std::int32_t>& order, std::int64_t chunk_begin,
                               std::int64_t chunk_end, int depth) {
  TEXSIM_VERIFY(depth <= kMaxDepth, "feature kd-tree: deeper than " << kMaxDepth);
  const auto first = static_cast<std::size_t>(chunk_begin * kLanes);
  const auto last = std::min(static_cast<std::size_t>(chunk_end * kLanes), order.size());
  float* low = boxes_.data() + static_cast<std::size_t>(node) * 2 * channels_;
  float* high = low + channels_;
  std::fill(low, high, std::numeric_limits<float>::infinity());
  std::fill(high, high + channels_, -std::numeric_limits<float>::infinity());
  for (std::size_t i = first; i < last; ++i) {
    const auto f = features.voxel(static_cast<std::size_t>(order[i]));
    for (int c = 0; c < channels_; ++c) {
      low[c] = std::min(low[c], f[static_cast<std::size_t>(c)]);
      high[c] = std::max(high[c], f[static_cast<std::size_t>(c)]);
    }
  }
  if (chunk_end - chunk_begin == 1) {
    nodes_[static_cast<std::size_t>(node)].chunk = static_cast<std::int32_t>(chunk_begin);
    float* block = lane_blocks_.data() + static_cast<std::size_t>(chunk_begin) * kLanes * channels_;
    for (std::size_t i = first; i < last; ++i) {
      const auto lane = i - first;
      voxels_[first + lane] = order[i];
      const auto f = features.voxel(static_cast<std::size_t>(order[i]));
      for (int c = 0; c < channels_; ++c)
        block[c * kLanes + lane] = f[static_cast<std::size_t>(c)];
    }
    return;
  }
  int axis = 0;
  for (int c = 1; c < channels_; ++c)
    if (high[c] - low[c] > high[axis] - low[axis])
      axis = c;
  // The voxel index breaks ties, so the split (and the whole tree) is the same on every rank.
  const std::int64_t middle_chunk = (chunk_begin + chunk_end) / 2;
  const auto by_axis = [&](std::int32_t a, std::int32_t b) {
    const float fa = features.voxel(static_cast<std::size_t>(a))[static_cast<std::size_t>(axis)];
    const float fb = features.voxel(static_cast<std::size_t>(b))[static_cast<std::size_t>(axis)];
    return fa < fb || (fa == fb && a < b);
  };
  std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(first),
                   order.begin() + static_cast<std::ptrdiff_t>(middle_chunk * kLanes),
                   order.begin() + static_cast<std::ptrdiff_t>(last), by_axis);
  const auto child = static_cast<std::int32_t>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  boxes_.resize(nodes_.size() * 2 * static_cast<std::size_t>(channels_));
  nodes_[static_cast<std::size_t>(node)].first_child = child;
  build_node(child, features, order, chunk_begin, middle_chunk, depth + 1);
  build_node(child + 1, features, order, middle_chunk, chunk_end, depth + 1);
}

float FeatureKdTree::box_distance(std::int32_t node, const float* query) const {
  // The float distance to the box's nearest point, clamp(q, low, high): a point of floats, so the
  // scan's rounding bound (FloatDistanceBound) covers it like a voxel. Branch-free.
  // Four partial sums, so the compiler can use one SIMD register for four channels (the rounding
  // bound holds for any summation order).
  const float* low = boxes_.data() + static_cast<std::size_t>(node) * 2 * channels_;
  const float* high = low + channels_;
  const auto gap_squared = [&](int c) {
    const float gap = std::max(std::max(low[c] - query[c], query[c] - high[c]), 0.0f);
    return gap * gap;
  };
  float partial[4] = {};
  int c = 0;
  for (; c + 4 <= channels_; c += 4)
    for (int lane = 0; lane < 4; ++lane)
      partial[lane] += gap_squared(c + lane);
  for (; c < channels_; ++c)
    partial[0] += gap_squared(c);
  return (partial[0] + partial[1]) + (partial[2] + partial[3]);
}

float FeatureKdTree::scan_leaf(std::int32_t chunk, const float* query, FeatureVisitor& visitor,
                               float threshold) const {
  const float* block = lane_blocks_.data() + static_cast<std::size_t>(chunk) * kLanes * channels_;
  float distances[kLanes] = {};
  for (int c = 0; c < channels_; ++c) {
    const float q = query[c];
    const float* lanes = block + c * kLanes;
    for (int lane = 0; lane < kLanes; ++lane) {
      const float diff = lanes[lane] - q;
      distances[lane] += diff * diff;
    }
  }
  for (unsigned below = lanes_below(distances, threshold); below != 0; below &= below - 1) {
    const int lane = __builtin_ctz(below);
    if (!(distances[lane] < threshold)) // an earlier visit shrank the radius
      continue;
    visitor.visit(voxels_[static_cast<std::size_t>(chunk) * kLanes + lane]);
    threshold = float_bound_.threshold(visitor.radius(), true);
  }
  return threshold;
}

void FeatureKdTree::search(const float* query, FeatureVisitor& visitor) const {
  // Strict: a node or lane is skipped only when its float distance (to the box's nearest point,
  // or to the voxel) proves every voxel in it farther than the radius, which changes only when a
  // voxel is visited.
  float threshold = float_bound_.threshold(visitor.radius(), true);
  // Depth first, nearer child first; each entry carries its box distance.
  std::array<std::pair<std::int32_t, float>, kMaxDepth + 2> stack;
  int top = 0;
  stack[top++] = {0, box_distance(0, query)};
  while (top > 0) {
    const auto [node, lower_bound] = stack[--top];
    if (!(lower_bound < threshold))
      continue;
    const Node& here = nodes_[static_cast<std::size_t>(node)];
    if (here.first_child < 0) {
      threshold = scan_leaf(here.chunk, query, visitor, threshold);
      continue;
    }
    const std::int32_t a = here.first_child, b = here.first_child + 1;
    const float to_a = box_distance(a, query), to_b = box_distance(b, query);
    if (to_a <= to_b) {
      stack[top++] = {b, to_b};
      stack[top++] = {a, to_a};
    } else {
      stack[top++] = {a, to_a};
      stack[top++] = {b, to_b};
    }
  }
}

std::size_t FeatureKdTree::memory_bytes() const {
  return lane_blocks_.size() * sizeof(float) + voxels_.size() * sizeof(std::int32_t) +
         nodes_.size() * sizeof(Node) + boxes_.size() * sizeof(float);
}

} // namespace texsim::pipelines::solid_synthesis
