#pragma once
/// A kd-tree over the voxels of a feature grid for exact searches whose radius shrinks as they go:
/// the similarity sets' shortlists (nearest_outside_windows) ask it for every voxel that can still
/// beat their current witnesses, instead of scanning all N voxels per query.
///
/// Median splits along the widest channel down to leaves of one 16-voxel lane block (the layout
/// of core/float_distance_scan), each node with its bounding box. A search descends nearer child
/// first (boxes compared 8 channels per SIMD operation, one clone per instruction set) and scans
/// a leaf's 16 lanes with the scan's one-query kernel; a node or lane is skipped only when its
/// float distance (to the box's nearest point, or to the voxel) proves it farther than the radius
/// (FloatDistanceBound, strict).
///
/// Written here rather than taken from nanoflann (which surface_synthesis' pruned search uses):
/// nanoflann evaluates leaf points one at a time in double; on the 64^3 marble features it
/// evaluated about 1,500 points per query at about 18 ns each: 5.6 s for the similarity sets at
/// -n 2, where this tree takes 1.5 s (scripts/bench similarity-set).
#include "core/float_distance_scan.hpp"
#include "par/node_shared_array.hpp"
#include "vol/channel_grid.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// The squared feature distance the exact searches are defined by: the sum over channels of
/// (double(a_c) - double(b_c))^2 in channel order. Channel c of a is a[c * a_stride].
inline double exact_feature_distance(const float* a, std::ptrdiff_t a_stride, const float* b,
                                     int channels) {
  double sum = 0.0;
  for (int c = 0; c < channels; ++c) {
    const double diff = static_cast<double>(a[c * a_stride]) - static_cast<double>(b[c]);
    sum += diff * diff;
  }
  return sum;
}

/// What a search reports to: its current radius, and the voxels that may lie within it.
class FeatureVisitor {
public:
  virtual ~FeatureVisitor() = default;
  /// Squared feature distance beyond which voxels may be skipped; may shrink during a search.
  virtual double radius() const = 0;
  /// A voxel whose squared distance to the query may be at most radius().
  virtual void visit(std::int32_t voxel) = 0;
};

class FeatureKdTree {
public:
  static constexpr int kMaxChannels = 64; ///< as many as the appearance space allows
  /// Builds the tree over every voxel of `features` (finite values no larger than
  /// FloatDistanceBound::largest_safe_value()), held by this rank alone.
  explicit FeatureKdTree(const vol::ChannelGrid& features);
  /// The same tree held once per node (about 40 bytes a voxel for 8 channels, which every rank
  /// would otherwise hold), built by each node's first rank straight into the node's shared
  /// windows: no rank holds a private copy as well. Collective over layout->world.
  FeatureKdTree(const vol::ChannelGrid& features, std::shared_ptr<const par::NodeLayout> layout);

  /// Visits every voxel whose exact squared distance to `query` (channels() floats of the grid's
  /// kind) is at most visitor.radius() (re-read after each visit), and some farther ones; each
  /// voxel at most once. Thread-safe.
  void search(const float* query, FeatureVisitor& visitor) const;

  /// The voxels in leaf order (-1 for padding): queries taken in this order reuse the same nodes
  /// from cache.
  std::span<const std::int32_t> leaf_order() const { return voxels_; }

private:
  struct Node {
    std::int32_t first_child = -1; ///< the second child follows it; -1: a leaf
    std::int32_t chunk = -1;       ///< a leaf's lane block
  };
  struct Arrays;
  struct SharedArrays;
  struct Builder;

  int channels_ = 0;
  int box_width_ = 0; ///< channels rounded up to whole SIMD groups
  FloatDistanceBound float_bound_;
  std::shared_ptr<const void> storage_;  ///< the arrays below point into it
  std::span<const float> lane_blocks_;   ///< per leaf: channels x 16 lanes, padding lanes +inf
  std::span<const std::int32_t> voxels_; ///< per leaf: 16 voxel ids (-1 for padding)
  std::span<const Node> nodes_;
  std::span<const float> boxes_; ///< per node: box_width_ lows, then box_width_ highs (padding 0)
};

} // namespace texsim::pipelines::solid_synthesis
