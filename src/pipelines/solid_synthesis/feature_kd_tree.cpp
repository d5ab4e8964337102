#include "pipelines/solid_synthesis/feature_kd_tree.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <span>
#include <utility>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr int kLanes = kScanLanes;
/// Channels per SIMD group of a box (one AVX2 register); boxes are padded to whole groups.
constexpr int kGroup = 8;
using Group = float __attribute__((vector_size(kGroup * sizeof(float))));
/// Deeper than any tree over 2^31 voxels (median splits halve the lane blocks).
constexpr int kMaxDepth = 40;

} // namespace

/// The lengths of the tree's arrays over `voxel_count` voxels: fixed before the build, since median
/// splits down to single lane blocks make a full binary tree of 2 chunks - 1 nodes.
struct TreeSizes {
  std::size_t lane_values = 0, voxels = 0, nodes = 0, box_values = 0;

  TreeSizes(std::int64_t voxel_count, int channels, int box_width) {
    TEXSIM_VERIFY(channels >= 1 && channels <= FeatureKdTree::kMaxChannels && voxel_count > 0 &&
                      voxel_count <= std::numeric_limits<std::int32_t>::max(),
                  "feature kd-tree: " << voxel_count << " voxels of " << channels
                                      << " channels cannot be indexed");
    const auto chunks = static_cast<std::size_t>((voxel_count + kLanes - 1) / kLanes);
    lane_values = chunks * kLanes * static_cast<std::size_t>(channels);
    voxels = chunks * kLanes;
    nodes = 2 * chunks - 1;
    box_values = nodes * 2 * static_cast<std::size_t>(box_width);
  }
};

/// The tree's arrays held by one rank.
struct FeatureKdTree::Arrays {
  std::vector<float> lane_blocks;
  std::vector<std::int32_t> voxels;
  std::vector<Node> nodes;
  std::vector<float> boxes;

  explicit Arrays(const TreeSizes& sizes)
      : lane_blocks(sizes.lane_values), voxels(sizes.voxels), nodes(sizes.nodes),
        boxes(sizes.box_values) {}
};

/// The tree's arrays held once per node.
struct FeatureKdTree::SharedArrays {
  par::NodeSharedBytes lane_blocks, voxels, nodes, boxes;

  SharedArrays(const std::shared_ptr<const par::NodeLayout>& layout, const TreeSizes& sizes)
      : lane_blocks(layout, sizes.lane_values * sizeof(float)),
        voxels(layout, sizes.voxels * sizeof(std::int32_t)),
        nodes(layout, sizes.nodes * sizeof(Node)), boxes(layout, sizes.box_values * sizeof(float)) {
  }
};

/// Builds the tree into arrays of TreeSizes' lengths (their previous contents do not matter).
struct FeatureKdTree::Builder {
  const vol::ChannelGrid& features;
  int box_width;
  std::span<float> lane_blocks;
  std::span<std::int32_t> voxels;
  std::span<Node> nodes;
  std::span<float> boxes;
  std::vector<std::int32_t> order{};
  std::size_t next_node = 1;

  void build() {
    std::fill(lane_blocks.begin(), lane_blocks.end(),
              std::numeric_limits<float>::infinity()); // padding lanes never hit
    std::fill(voxels.begin(), voxels.end(), -1);
    std::fill(nodes.begin(), nodes.end(), Node{});
    std::fill(boxes.begin(), boxes.end(), 0.0f); // padding channels stay 0
    order.resize(features.voxel_count());
    for (std::size_t v = 0; v < order.size(); ++v)
      order[v] = static_cast<std::int32_t>(v);
    build_node(0, 0, static_cast<std::int64_t>(voxels.size() / kLanes), 0);
    TEXSIM_VERIFY(next_node == nodes.size(),
                  "feature kd-tree: " << next_node << " nodes built, " << nodes.size() << " sized");
  }

  /// Fills node `node` with the voxels order[16 chunk_begin, min(16 chunk_end, voxel count)),
  /// split at the median of their widest channel until one lane block is left.
  void build_node(std::size_t node, std::int64_t chunk_begin, std::int64_t chunk_end, int depth);
};

FeatureKdTree::FeatureKdTree(const vol::ChannelGrid& features)
    : channels_(features.channels()),
      box_width_((features.channels() + kGroup - 1) / kGroup * kGroup),
      float_bound_(features.channels()) {
  auto arrays = std::make_shared<Arrays>(
      TreeSizes(static_cast<std::int64_t>(features.voxel_count()), channels_, box_width_));
  Builder{features, box_width_, arrays->lane_blocks, arrays->voxels, arrays->nodes, arrays->boxes}
      .build();
  lane_blocks_ = arrays->lane_blocks;
  voxels_ = arrays->voxels;
  nodes_ = arrays->nodes;
  boxes_ = arrays->boxes;
  storage_ = std::move(arrays);
}

namespace {

template <class T> std::span<T> as_span(const par::NodeSharedBytes& bytes) {
  return {reinterpret_cast<T*>(bytes.bytes().data()), bytes.bytes().size() / sizeof(T)};
}

} // namespace

FeatureKdTree::FeatureKdTree(const vol::ChannelGrid& features,
                             std::shared_ptr<const par::NodeLayout> layout)
    : channels_(features.channels()),
      box_width_((features.channels() + kGroup - 1) / kGroup * kGroup),
      float_bound_(features.channels()) {
  auto shared = std::make_shared<SharedArrays>(
      layout, TreeSizes(static_cast<std::int64_t>(features.voxel_count()), channels_, box_width_));
  const auto lane_blocks = as_span<float>(shared->lane_blocks);
  const auto voxels = as_span<std::int32_t>(shared->voxels);
  const auto nodes = as_span<Node>(shared->nodes);
  const auto boxes = as_span<float>(shared->boxes);
  // Each node's first rank builds (the same tree on every node); an error there reaches every
  // rank.
  par::run_collectively(layout->world, [&] {
    if (layout->node.rank == 0)
      Builder{features, box_width_, lane_blocks, voxels, nodes, boxes}.build();
  });
  for (const par::NodeSharedBytes* bytes :
       {&shared->lane_blocks, &shared->voxels, &shared->nodes, &shared->boxes})
    bytes->synchronise();
  lane_blocks_ = lane_blocks;
  voxels_ = voxels;
  nodes_ = nodes;
  boxes_ = boxes;
  storage_ = std::move(shared);
}

void FeatureKdTree::Builder::build_node(std::size_t node, std::int64_t chunk_begin,
                                        std::int64_t chunk_end, int depth) {
  TEXSIM_VERIFY(depth <= kMaxDepth, "feature kd-tree: deeper than " << kMaxDepth);
  const int channels = features.channels();
  const auto first = static_cast<std::size_t>(chunk_begin * kLanes);
  const auto last = std::min(static_cast<std::size_t>(chunk_end * kLanes), order.size());
  float* low = boxes.data() + node * 2 * static_cast<std::size_t>(box_width);
  float* high = low + box_width;
  std::fill(low, low + channels, std::numeric_limits<float>::infinity());
  std::fill(high, high + channels, -std::numeric_limits<float>::infinity());
  for (std::size_t i = first; i < last; ++i) {
    const auto f = features.voxel(static_cast<std::size_t>(order[i]));
    for (int c = 0; c < channels; ++c) {
      low[c] = std::min(low[c], f[static_cast<std::size_t>(c)]);
      high[c] = std::max(high[c], f[static_cast<std::size_t>(c)]);
    }
  }
  if (chunk_end - chunk_begin == 1) {
    nodes[node].chunk = static_cast<std::int32_t>(chunk_begin);
    float* block = lane_blocks.data() + static_cast<std::size_t>(chunk_begin) * kLanes * channels;
    for (std::size_t i = first; i < last; ++i) {
      const auto lane = i - first;
      voxels[first + lane] = order[i];
      const auto f = features.voxel(static_cast<std::size_t>(order[i]));
      for (int c = 0; c < channels; ++c)
        block[c * kLanes + lane] = f[static_cast<std::size_t>(c)];
    }
    return;
  }
  int axis = 0;
  for (int c = 1; c < channels; ++c)
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
  const std::size_t child = next_node;
  next_node += 2;
  nodes[node].first_child = static_cast<std::int32_t>(child);
  build_node(child, chunk_begin, middle_chunk, depth + 1);
  build_node(child + 1, middle_chunk, chunk_end, depth + 1);
}

namespace {

/// Float squared distance from a query (padded with zeros to `groups` x kGroup channels) to a
/// box: the distance to its nearest point, clamp(q, low, high), whose coordinates are floats, so
/// the scan's rounding bound (FloatDistanceBound, any summation order) covers it like a voxel.
[[gnu::always_inline]] inline float box_distance(const float* box, const float* query, int groups) {
  const float* low = box;
  const float* high = box + groups * kGroup;
  Group sum = {};
  for (int g = 0; g < groups; ++g) {
    Group lo, hi, q;
    std::memcpy(&lo, low + g * kGroup, sizeof lo);
    std::memcpy(&hi, high + g * kGroup, sizeof hi);
    std::memcpy(&q, query + g * kGroup, sizeof q);
    const Group below = lo - q, above = q - hi;
    Group gap = below > above ? below : above;
    gap = gap > Group{} ? gap : Group{};
    sum += gap * gap;
  }
  return ((sum[0] + sum[1]) + (sum[2] + sum[3])) + ((sum[4] + sum[5]) + (sum[6] + sum[7]));
}

/// A leaf's lanes under the threshold, as the scan kernel reports them: visited, and the
/// threshold follows the visitor's shrinking radius.
struct LeafVisits {
  const FloatDistanceBound* bound;
  const std::int32_t* voxels;
  FeatureVisitor* visitor;
  float thresholds[kScanQueries];
};

void visit_lanes(void* context, std::int64_t chunk, const float* distances) {
  auto& leaf = *static_cast<LeafVisits*>(context);
  float& threshold = leaf.thresholds[0];
  for (unsigned below = lanes_below(distances, threshold); below != 0; below &= below - 1) {
    const int lane = __builtin_ctz(below);
    if (!(distances[lane] < threshold)) // an earlier visit shrank the radius
      continue;
    leaf.visitor->visit(leaf.voxels[chunk * kLanes + lane]);
    threshold = leaf.bound->threshold(leaf.visitor->radius(), true);
  }
}

} // namespace

__attribute__((target_clones("avx512f", "avx2", "default"))) void
FeatureKdTree::search(const float* query, FeatureVisitor& visitor) const {
  // Strict thresholds: a node or lane is skipped only when its float distance (to the box's
  // nearest point, or to the voxel) proves every voxel in it farther than the radius, which
  // changes only when a voxel is visited.
  const int groups = box_width_ / kGroup;
  float padded[kMaxChannels] = {};
  std::copy(query, query + channels_, padded);
  LeafVisits leaf{&float_bound_, voxels_.data(), &visitor, {}};
  float& threshold = leaf.thresholds[0];
  threshold = float_bound_.threshold(visitor.radius(), true);
  FloatDistanceScan scan{};
  scan.lane_blocks = lane_blocks_.data();
  scan.channels = channels_;
  scan.query_features = query;
  scan.thresholds = leaf.thresholds;
  scan.on_hit = visit_lanes;
  scan.context = &leaf;
  const auto box_of = [&](std::int32_t node) {
    return boxes_.data() + static_cast<std::size_t>(node) * 2 * box_width_;
  };

  // Depth first, nearer child first; each entry carries its box distance.
  std::array<std::pair<std::int32_t, float>, kMaxDepth + 2> stack;
  int top = 0;
  stack[top++] = {0, box_distance(box_of(0), padded, groups)};
  while (top > 0) {
    const auto [node, lower_bound] = stack[--top];
    if (!(lower_bound < threshold))
      continue;
    const Node& here = nodes_[static_cast<std::size_t>(node)];
    if (here.first_child < 0) {
      scan.chunk_begin = here.chunk;
      scan.chunk_end = here.chunk + 1;
      scan_float_distances(ScanKernel::kSingle, scan);
      continue;
    }
    const std::int32_t a = here.first_child, b = here.first_child + 1;
    const float to_a = box_distance(box_of(a), padded, groups);
    const float to_b = box_distance(box_of(b), padded, groups);
    if (to_a <= to_b) {
      stack[top++] = {b, to_b};
      stack[top++] = {a, to_a};
    } else {
      stack[top++] = {a, to_a};
      stack[top++] = {b, to_b};
    }
  }
}

} // namespace texsim::pipelines::solid_synthesis
