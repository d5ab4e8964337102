#pragma once
/// The distance kernel of the similarity sets: for query voxels p, every exemplar voxel that can
/// still be one of p's k - 1 best matches outside the exclusion windows, with exact results, found
/// by one of two searches:
/// - tree: a kd-tree over the features (feature_kd_tree) visits only the voxels
///   within the current witness distance of p, which shrinks as witnesses are found;
/// - scan: one pass over all voxels per block of queries (the brute-force kernel, kept as the
///   reference the benchmark measures the tree against, and the cheaper one on small grids).
///
/// The scan's fast pass (core/float_distance_scan: register-blocked, 8 queries x 16 voxels,
/// features stored in 16-voxel lane blocks, one SIMD clone per instruction set) compares float
/// distances against a per-query threshold; the few voxels under it get their exact double distance
/// and enter a sorted shortlist. A voxel x can be dropped once the shortlist holds k - 1 voxels
/// better than x (exact distance, then voxel index), outside p's window and pairwise more than 2 *
/// half apart: no window holds two of them, so whichever k - 2 further windows the greedy selection
/// opens, one of them stays better than x. The threshold carries a bound on the float rounding, so
/// a voxel the fast pass skips is always provably droppable.
#include "core/float_distance_scan.hpp"
#include "par/node_shared_array.hpp"
#include "vol/channel_grid.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// Exclusion windows on the exemplar grid: voxel b lies in the window centred on a when
/// |dx|, |dy|, |dz| <= half, with toroidal differences when periodic and plain ones otherwise.
struct ExclusionWindows {
  vol::Dims dims;
  int half = 0;
  bool periodic = true;

  /// (x, y, z) of a storage index (x fastest).
  std::array<int, 3> coordinates(std::int32_t voxel) const {
    const int x = voxel % dims.nx;
    const int rest = voxel / dims.nx;
    return {x, rest % dims.ny, rest / dims.ny};
  }
  /// |a - b| along an axis of n voxels, the shorter way round when periodic.
  int axis_distance(int a, int b, int n) const {
    const int d = a > b ? a - b : b - a;
    return periodic && n - d < d ? n - d : d;
  }
  /// Largest axis distance (the infinity norm of the toroidal or plain difference).
  int distance(const std::array<int, 3>& a, const std::array<int, 3>& b) const {
    const int dx = axis_distance(a[0], b[0], dims.nx);
    const int dy = axis_distance(a[1], b[1], dims.ny);
    const int dz = axis_distance(a[2], b[2], dims.nz);
    return dx > dy ? (dx > dz ? dx : dz) : (dy > dz ? dy : dz);
  }
  /// Whether `voxel` lies in the window centred on `centre`.
  bool inside(const std::array<int, 3>& centre, const std::array<int, 3>& voxel) const {
    return distance(centre, voxel) <= half;
  }
  /// Whether no window holds both voxels.
  bool far_apart(const std::array<int, 3>& a, const std::array<int, 3>& b) const {
    return distance(a, b) > 2 * half;
  }
};

/// A voxel and its squared feature distance to a query, ordered by distance, then voxel index (the
/// order that decides the similarity sets).
struct RankedVoxel {
  double distance = 0.0;
  std::int32_t voxel = 0;
  friend bool operator<(const RankedVoxel& a, const RankedVoxel& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.voxel < b.voxel);
  }
};

/// How shortlists are searched (the same shortlists either way). automatic: the tree, unless the
/// grid is small (under 32^3 voxels, where the scan is cheap). Exact ties (voxels with identical
/// features, thousands in flat colours or a tiling exemplar) would make the tree visit them one
/// by one; similarity_sets settles the queries they decide before any search (feature_twins).
enum class ShortlistSearch { automatic, tree, scan };

/// The search `automatic` picks for these features.
ShortlistSearch automatic_search(const vol::ChannelGrid& features);

class FeatureKdTree;

/// Shortlists of candidate voxels for query voxels, over one exemplar. Construction builds the
/// kd-tree or copies the features into lane blocks (both node-shared); shortlists() is
/// thread-safe.
class NearestOutsideWindows {
public:
  /// `witnesses` = k - 1 >= 1: how many pairwise far-apart better voxels drop a voxel. Features
  /// must be finite and small enough that float squared distances cannot overflow.
  /// The kd-tree (built on layout->world's rank 0) or the scan's lane blocks (filled by the
  /// node's ranks in shares) are held once per node. Collective over layout->world.
  NearestOutsideWindows(const vol::ChannelGrid& features, const ExclusionWindows& windows,
                        int witnesses, ShortlistSearch search,
                        std::shared_ptr<const par::NodeLayout> layout);
  ~NearestOutsideWindows();

  /// For each query voxel q: the voxels outside q's window that may be among its k - 1 greedy
  /// picks, sorted by (exact distance, voxel). Every voxel outside the window that is not listed
  /// is worse than k - 1 listed voxels that are pairwise far apart.
  std::vector<std::vector<RankedVoxel>>
  shortlists(std::span<const std::int32_t> query_voxels) const;

  /// The voxel at `position` of the order queries are cheapest in, which visits every voxel once:
  /// the tree's leaf order (neighbours in feature space, so consecutive searches find the same
  /// nodes in cache), or the grid's for the scan (neighbours in the grid share the window rows).
  std::int32_t query_at(std::size_t position) const {
    return tree_ ? tree_order_[position] : static_cast<std::int32_t>(position);
  }

private:
  struct QueryState;
  struct Block;
  class TreeVisitor;
  /// Offers every voxel within reach of the queries: one pass over all lane blocks.
  void scan(std::vector<QueryState>& queries) const;
  /// Offers the voxels the kd-tree finds within the query's bound.
  void search_tree(QueryState& query) const;
  void scan_block(Block& block, std::int64_t row_begin, std::int64_t row_end) const;
  void accept_hits(Block& block, std::int64_t chunk, const float* distances) const;
  void seed(QueryState& query) const;
  /// Channel c of the voxel's features is voxel_features[c * stride].
  void offer(QueryState& query, const float* query_features, std::int32_t voxel,
             const float* voxel_features, std::ptrdiff_t stride) const;
  void merge_pending(QueryState& query) const;
  std::size_t last_witness(const std::vector<RankedVoxel>& sorted) const;
  float threshold(const QueryState& query) const;

  const vol::ChannelGrid& features_;
  ExclusionWindows windows_;
  int witnesses_;
  int channels_;
  int chunks_per_row_;
  int rows_per_tile_;
  FloatDistanceBound float_bound_;
  /// scan: per 16-voxel chunk of a row, channel-major, 16 lanes; held once per node
  par::NodeSharedArray<float> lane_blocks_;
  std::unique_ptr<FeatureKdTree> tree_; ///< tree search
  /// The tree's leaf order without its padding lanes, held once per node.
  par::NodeSharedArray<std::int32_t> tree_order_;
};

} // namespace texsim::pipelines::solid_synthesis
