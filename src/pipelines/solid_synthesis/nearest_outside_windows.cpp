#include "pipelines/solid_synthesis/nearest_outside_windows.hpp"

#include "core/error.hpp"
#include "core/float_distance_scan.hpp"
#include "pipelines/solid_synthesis/feature_kd_tree.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr int kLanes = kScanLanes;
constexpr int kQueryBlock = kScanQueries;
constexpr int kMaxWitnesses = 63; ///< k - 1 limit (the greedy witness picks live on the stack)
/// Offers collected before the shortlist is merged: the scan batches them (its threshold is
/// refreshed per hit anyway); the tree merges at once, since a tighter bound prunes whole cells.
constexpr std::size_t kScanBatch = 16;
constexpr std::size_t kTreeBatch = 1;
constexpr std::size_t kTileBytes = 128 * 1024; ///< lane blocks scanned per pass over the queries

} // namespace

struct NearestOutsideWindows::QueryState {
  std::int32_t voxel = 0;
  std::array<int, 3> at{};
  std::vector<RankedVoxel> shortlist;
  std::vector<RankedVoxel> pending; ///< offered since the last merge, unsorted
  /// The last of the best k - 1 pairwise far-apart shortlist witnesses so far: voxels after it in
  /// (distance, voxel) order can be dropped.
  RankedVoxel bound{std::numeric_limits<double>::infinity(),
                    std::numeric_limits<std::int32_t>::max()};
  /// Distance of the last of k - 1 pairwise far-apart seed voxels: farther voxels can be dropped.
  double seed_bound = std::numeric_limits<double>::infinity();
};

struct NearestOutsideWindows::Block {
  int count = 0; ///< queries in use (the last block of a range may be partial)
  QueryState* queries[kQueryBlock] = {};
  std::vector<float> query_features; ///< kQueryBlock x channels
  float thresholds[kQueryBlock] = {};
  std::vector<float> penalties;          ///< kQueryBlock x chunks_per_row x kLanes
  std::vector<float> no_penalty;         ///< chunks_per_row x kLanes zeros
  std::vector<std::int64_t> window_rows; ///< rows crossing some query's window, ascending
};

ShortlistSearch automatic_search(const vol::ChannelGrid& features) {
  constexpr std::size_t kSmallGrid = 32 * 32 * 32;
  return features.voxel_count() < kSmallGrid ? ShortlistSearch::scan : ShortlistSearch::tree;
}

NearestOutsideWindows::NearestOutsideWindows(const vol::ChannelGrid& features,
                                             const ExclusionWindows& windows, int witnesses,
                                             ShortlistSearch search,
                                             std::shared_ptr<const par::NodeLayout> layout)
    : features_(features), windows_(windows), witnesses_(witnesses), channels_(features.channels()),
      chunks_per_row_((features.dims().nx + kLanes - 1) / kLanes), float_bound_(channels_) {
  TEXSIM_VERIFY(witnesses_ >= 1 && witnesses_ <= kMaxWitnesses,
                "similarity sets: shortlists need 2 <= k <= " << kMaxWitnesses + 1
                                                              << ", got k = " << witnesses_ + 1);
  TEXSIM_VERIFY(features.dims() == windows.dims, "similarity sets: window grid differs from the "
                                                 "feature grid");
  const float safe = float_bound_.largest_safe_value();
  for (const float f : features.data())
    TEXSIM_VERIFY(std::isfinite(f) && std::abs(f) <= safe,
                  "similarity sets: feature value " << f << " is not finite or exceeds " << safe);
  if (search == ShortlistSearch::automatic)
    search = automatic_search(features);
  if (search == ShortlistSearch::tree) {
    tree_ = std::make_unique<FeatureKdTree>(features, layout);
    std::vector<std::int32_t> order; // rank 0's, until the node windows hold it
    if (layout->world.rank == 0) {
      order.reserve(features.voxel_count());
      for (const std::int32_t voxel : tree_->leaf_order())
        if (voxel >= 0) // not a padding lane
          order.push_back(voxel);
    }
    tree_order_ = par::NodeSharedArray<std::int32_t>::from_root(std::move(layout), order);
    return;
  }

  const vol::Dims dims = features.dims();
  const std::size_t rows = static_cast<std::size_t>(dims.ny) * static_cast<std::size_t>(dims.nz);
  const std::size_t chunk_floats = static_cast<std::size_t>(channels_) * kLanes;
  rows_per_tile_ = static_cast<int>(
      std::max<std::size_t>(1, kTileBytes / (chunk_floats * sizeof(float) * chunks_per_row_)));
  // Held once per node; each of the node's ranks fills a share of the rows.
  const std::size_t row_floats = chunks_per_row_ * chunk_floats;
  lane_blocks_ = par::NodeSharedArray<float>::filled(
      std::move(layout), rows * row_floats,
      [&](std::span<float> all, std::size_t begin, std::size_t end) {
        std::fill(all.begin() + static_cast<std::ptrdiff_t>(begin),
                  all.begin() + static_cast<std::ptrdiff_t>(end),
                  std::numeric_limits<float>::infinity()); // padding lanes never hit
        for (std::size_t row = begin / row_floats; row < end / row_floats; ++row)
          for (int x = 0; x < dims.nx; ++x) {
            const auto f = features.voxel(row * static_cast<std::size_t>(dims.nx) + x);
            float* chunk = all.data() + row * row_floats + (x / kLanes) * chunk_floats;
            for (int c = 0; c < channels_; ++c)
              chunk[c * kLanes + x % kLanes] = f[static_cast<std::size_t>(c)];
          }
      },
      row_floats);
}

NearestOutsideWindows::~NearestOutsideWindows() = default;

float NearestOutsideWindows::threshold(const QueryState& query) const {
  // Shortlist witnesses were all scanned before any voxel still to come, which therefore has a
  // larger index: equal distance already puts it after them. Seed witnesses may come later in the
  // scan, so they drop only voxels strictly farther than all of them.
  return std::min(float_bound_.threshold(query.bound.distance, false),
                  float_bound_.threshold(query.seed_bound, true));
}

std::size_t NearestOutsideWindows::last_witness(const std::vector<RankedVoxel>& sorted) const {
  // Greedy in (distance, voxel) order: each pick is far from every earlier pick.
  std::array<int, 3> picks[kMaxWitnesses];
  int picked = 0;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const auto at = windows_.coordinates(sorted[i].voxel);
    bool far = true;
    for (int p = 0; p < picked && far; ++p)
      far = windows_.far_apart(picks[p], at);
    if (!far)
      continue;
    if (picked + 1 == witnesses_)
      return i;
    picks[picked++] = at;
  }
  return sorted.size();
}

void NearestOutsideWindows::seed(QueryState& query) const {
  const float* query_features = features_.voxel(static_cast<std::size_t>(query.voxel)).data();
  const auto distance_to = [&](std::int32_t voxel) {
    return RankedVoxel{
        exact_feature_distance(features_.voxel(static_cast<std::size_t>(voxel)).data(), 1,
                               query_features, channels_),
        voxel};
  };
  // The voxels one step outside the window along each axis direction and diagonal: for smooth
  // features they are among the best matches, so the threshold starts close to its final value.
  const vol::Dims dims = features_.dims();
  const int step = windows_.half + 1;
  std::vector<RankedVoxel> seeds;
  for (int dz = -step; dz <= step; dz += step)
    for (int dy = -step; dy <= step; dy += step)
      for (int dx = -step; dx <= step; dx += step) {
        std::array<int, 3> at{query.at[0] + dx, query.at[1] + dy, query.at[2] + dz};
        const int sizes[3] = {dims.nx, dims.ny, dims.nz};
        bool in_grid = true;
        for (int axis = 0; axis < 3; ++axis) {
          if (windows_.periodic)
            at[axis] = vol::ChannelGrid::wrap(at[axis], sizes[axis]);
          in_grid = in_grid && at[axis] >= 0 && at[axis] < sizes[axis];
        }
        if (!in_grid || windows_.inside(query.at, at))
          continue;
        seeds.push_back(
            distance_to(static_cast<std::int32_t>(features_.index(at[0], at[1], at[2]))));
      }
  std::sort(seeds.begin(), seeds.end());
  const std::size_t last = last_witness(seeds);
  if (last < seeds.size())
    query.seed_bound = seeds[last].distance;
}

void NearestOutsideWindows::merge_pending(QueryState& query) const {
  auto& list = query.shortlist;
  const auto middle = static_cast<std::ptrdiff_t>(list.size());
  std::sort(query.pending.begin(), query.pending.end());
  list.insert(list.end(), query.pending.begin(), query.pending.end());
  query.pending.clear();
  std::inplace_merge(list.begin(), list.begin() + middle, list.end());
  const std::size_t last = last_witness(list);
  if (last < list.size() && list[last] < query.bound) {
    query.bound = list[last];
    list.resize(last + 1);
  }
}

void NearestOutsideWindows::offer(QueryState& query, const float* query_features,
                                  std::int32_t voxel, const float* voxel_features,
                                  std::ptrdiff_t stride) const {
  if (windows_.inside(query.at, windows_.coordinates(voxel)))
    return;
  const RankedVoxel candidate{
      exact_feature_distance(voxel_features, stride, query_features, channels_), voxel};
  if (!(candidate < query.bound) || candidate.distance > query.seed_bound)
    return;
  // Offers are batched: the witnesses are looked for again once the batch is half the shortlist,
  // so a query collecting many candidates (no far-apart witnesses yet) costs O(n log n), not n^2.
  query.pending.push_back(candidate);
  if (query.pending.size() >= std::max(tree_ ? kTreeBatch : kScanBatch, query.shortlist.size() / 2))
    merge_pending(query);
}

void NearestOutsideWindows::accept_hits(Block& block, std::int64_t chunk,
                                        const float* distances) const {
  const std::int64_t row = chunk / chunks_per_row_;
  const int first_x = static_cast<int>(chunk % chunks_per_row_) * kLanes;
  const std::int64_t row_start = row * features_.dims().nx;
  const float* chunk_features = lane_blocks_.data() + chunk * channels_ * kLanes;
  for (int j = 0; j < block.count; ++j) {
    const float* lanes = distances + j * kLanes;
    for (unsigned below = lanes_below(lanes, block.thresholds[j]); below != 0; below &= below - 1) {
      const int lane = __builtin_ctz(below);
      if (!(lanes[lane] < block.thresholds[j])) // an earlier lane lowered the threshold
        continue;
      QueryState& query = *block.queries[j];
      // The voxel's features from the lane block just scanned (in cache), not from the grid.
      offer(query, block.query_features.data() + j * channels_,
            static_cast<std::int32_t>(row_start + first_x + lane), chunk_features + lane, kLanes);
      block.thresholds[j] = threshold(query);
    }
  }
}

void NearestOutsideWindows::scan_block(Block& block, std::int64_t row_begin,
                                       std::int64_t row_end) const {
  const vol::Dims dims = features_.dims();
  // Rows crossing a query's window get the SIMD penalties (its window lanes never hit); the
  // others, all but about window^2 of them, are scanned plain in long runs.
  const auto in_window = [&](int j, std::int64_t row) {
    const QueryState& query = *block.queries[j];
    const int y = static_cast<int>(row % dims.ny);
    const int z = static_cast<int>(row / dims.ny);
    return windows_.axis_distance(y, query.at[1], dims.ny) <= windows_.half &&
           windows_.axis_distance(z, query.at[2], dims.nz) <= windows_.half;
  };
  struct HitContext {
    const NearestOutsideWindows* self;
    Block* block;
  } context{this, &block};
  FloatDistanceScan scan{};
  scan.lane_blocks = lane_blocks_.data();
  scan.channels = channels_;
  scan.query_features = block.query_features.data();
  scan.thresholds = block.thresholds;
  scan.on_hit = [](void* c, std::int64_t chunk, const float* distances) {
    auto* hit = static_cast<HitContext*>(c);
    hit->self->accept_hits(*hit->block, chunk, distances);
  };
  scan.context = &context;
  const auto& masked = block.window_rows;
  auto next_masked = std::lower_bound(masked.begin(), masked.end(), row_begin);
  for (std::int64_t row = row_begin; row < row_end;) {
    if (next_masked != masked.end() && *next_masked == row) {
      ++next_masked;
      for (int j = 0; j < kQueryBlock; ++j)
        scan.penalties[j] = j < block.count && in_window(j, row)
                                ? block.penalties.data() + j * chunks_per_row_ * kLanes
                                : block.no_penalty.data();
      scan.chunk_begin = row * chunks_per_row_;
      scan.chunk_end = scan.chunk_begin + chunks_per_row_;
      scan_float_distances(ScanKernel::kMasked, scan);
      ++row;
      continue;
    }
    const std::int64_t run_end =
        next_masked != masked.end() ? std::min(*next_masked, row_end) : row_end;
    scan.chunk_begin = row * chunks_per_row_;
    scan.chunk_end = run_end * chunks_per_row_;
    scan_float_distances(ScanKernel::kBlock, scan);
    row = run_end;
  }
}

/// The tree search's view of one query: the radius is the query's current bound, and every
/// visited voxel is offered like a scan hit.
class NearestOutsideWindows::TreeVisitor final : public FeatureVisitor {
public:
  TreeVisitor(const NearestOutsideWindows& self, QueryState& query, const float* query_features)
      : self_(self), query_(query), query_features_(query_features) {}
  double radius() const override { return std::min(query_.bound.distance, query_.seed_bound); }
  void visit(std::int32_t voxel) override {
    self_.offer(query_, query_features_, voxel,
                self_.features_.voxel(static_cast<std::size_t>(voxel)).data(), 1);
  }

private:
  const NearestOutsideWindows& self_;
  QueryState& query_;
  const float* query_features_;
};

void NearestOutsideWindows::search_tree(QueryState& query) const {
  const float* query_features = features_.voxel(static_cast<std::size_t>(query.voxel)).data();
  TreeVisitor visitor(*this, query, query_features);
  tree_->search(query_features, visitor);
}

std::vector<std::vector<RankedVoxel>>
NearestOutsideWindows::shortlists(std::span<const std::int32_t> query_voxels) const {
  const int count = static_cast<int>(query_voxels.size());
  std::vector<QueryState> queries(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    queries[i].voxel = query_voxels[static_cast<std::size_t>(i)];
    queries[i].at = windows_.coordinates(queries[i].voxel);
  }
  for (QueryState& query : queries)
    seed(query);
  if (tree_) {
    for (QueryState& query : queries)
      search_tree(query);
  } else {
    scan(queries);
  }
  for (QueryState& query : queries)
    merge_pending(query);
  std::vector<std::vector<RankedVoxel>> lists(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i)
    lists[i] = std::move(queries[i].shortlist);
  return lists;
}

void NearestOutsideWindows::scan(std::vector<QueryState>& queries) const {
  const vol::Dims dims = features_.dims();
  const int count = static_cast<int>(queries.size());

  // Blocks of kQueryBlock queries: their features, thresholds and window penalties per lane.
  std::vector<Block> blocks(static_cast<std::size_t>((count + kQueryBlock - 1) / kQueryBlock));
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    Block& block = blocks[b];
    block.count = std::min(kQueryBlock, count - static_cast<int>(b) * kQueryBlock);
    block.query_features.assign(static_cast<std::size_t>(kQueryBlock) * channels_, 0.0f);
    block.penalties.assign(static_cast<std::size_t>(kQueryBlock) * chunks_per_row_ * kLanes, 0.0f);
    block.no_penalty.assign(static_cast<std::size_t>(chunks_per_row_) * kLanes, 0.0f);
    for (int j = 0; j < kQueryBlock; ++j) {
      block.thresholds[j] = kScanNeverHits;
      if (j >= block.count)
        continue;
      QueryState& query = queries[b * kQueryBlock + j];
      block.thresholds[j] = threshold(query);
      block.queries[j] = &query;
      const auto f = features_.voxel(static_cast<std::size_t>(query.voxel));
      std::copy(f.begin(), f.end(), block.query_features.begin() + j * channels_);
      for (int x = 0; x < dims.nx; ++x)
        if (windows_.axis_distance(x, query.at[0], dims.nx) <= windows_.half)
          block.penalties[(static_cast<std::size_t>(j) * chunks_per_row_) * kLanes + x] =
              std::numeric_limits<float>::infinity();
      for (int dz = -windows_.half; dz <= windows_.half; ++dz)
        for (int dy = -windows_.half; dy <= windows_.half; ++dy) {
          int y = query.at[1] + dy, z = query.at[2] + dz;
          if (windows_.periodic) {
            y = vol::ChannelGrid::wrap(y, dims.ny);
            z = vol::ChannelGrid::wrap(z, dims.nz);
          }
          if (y >= 0 && y < dims.ny && z >= 0 && z < dims.nz)
            block.window_rows.push_back(y + static_cast<std::int64_t>(dims.ny) * z);
        }
    }
    std::sort(block.window_rows.begin(), block.window_rows.end());
    block.window_rows.erase(std::unique(block.window_rows.begin(), block.window_rows.end()),
                            block.window_rows.end());
  }

  const std::int64_t rows = static_cast<std::int64_t>(dims.ny) * dims.nz;
  for (std::int64_t tile = 0; tile < rows; tile += rows_per_tile_)
    for (Block& block : blocks)
      scan_block(block, tile, std::min<std::int64_t>(rows, tile + rows_per_tile_));
}

} // namespace texsim::pipelines::solid_synthesis
