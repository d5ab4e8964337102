#include "pipelines/solid_synthesis/similarity_sets.hpp"

#include "core/error.hpp"
#include "core/progress.hpp"
#include "pipelines/solid_synthesis/feature_twins.hpp"
#include "pipelines/solid_synthesis/nearest_outside_windows.hpp"

#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <memory>
#include <ranges>
#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Query voxels per OpenMP task: enough to reuse each feature tile across 16 register blocks,
/// few enough that dynamic scheduling balances the threads.
constexpr std::int32_t kQueriesPerTask = 128;
/// Largest k (the chosen candidates' coordinates live on the stack).
constexpr int kMaxCandidates = 64;

/// The greedy selection of section 3.2 over `voxels` in (distance, voxel) order: C_1 = p, then
/// each next voxel outside the windows of the candidates chosen so far, until k are chosen.
/// Returns how many were (the rest of `out` is untouched).
template <class Voxels>
int select_candidates(std::int32_t query, const Voxels& voxels, const ExclusionWindows& windows,
                      int k, std::int32_t* out) {
  std::array<int, 3> chosen_at[kMaxCandidates];
  out[0] = query;
  chosen_at[0] = windows.coordinates(query);
  int chosen = 1;
  for (const std::int32_t voxel : voxels) {
    if (chosen == k)
      break;
    const auto at = windows.coordinates(voxel);
    bool outside = true;
    for (int c = 0; c < chosen && outside; ++c)
      outside = !windows.inside(chosen_at[c], at);
    if (outside) {
      out[chosen] = voxel;
      chosen_at[chosen++] = at;
    }
  }
  return chosen;
}

/// When no voxel is left outside the windows (tiny exemplars), the last candidate repeats.
void repeat_last(int chosen, int k, std::int32_t* out) {
  for (; chosen < k; ++chosen)
    out[chosen] = out[chosen - 1];
}

} // namespace

SimilaritySets build_similarity_sets(const par::Comm& comm, const vol::ChannelGrid& features,
                                     const SimilarityOptions& options) {
  TEXSIM_VERIFY(options.k >= 1 && options.k <= kMaxCandidates,
                "similarity sets: k must be in [1, " << kMaxCandidates << "], got " << options.k);
  TEXSIM_VERIFY(options.window >= 1,
                "similarity sets: window must be positive, got " << options.window);
  const std::size_t voxels = features.voxel_count();
  TEXSIM_VERIFY(voxels > 0 && voxels <= static_cast<std::size_t>(
                                            std::numeric_limits<std::int32_t>::max() / options.k),
                "similarity sets: " << voxels << " voxels do not fit 32-bit candidate indices");
  const auto n = static_cast<std::int32_t>(voxels);
  const int k = options.k;
  const ExclusionWindows windows{features.dims(), options.window / 2, options.periodic};

  // Queries in the search's cheapest order; this rank takes a contiguous range of positions.
  // The tree and the twins are built on rank 0 and held once per node.
  const auto layout = par::NodeLayout::make(comm);
  std::unique_ptr<NearestOutsideWindows> scanner;
  if (k > 1)
    scanner =
        std::make_unique<NearestOutsideWindows>(features, windows, k - 1, options.search, layout);
  const auto query_at = [&](std::size_t position) {
    return scanner ? scanner->query_at(position) : static_cast<std::int32_t>(position);
  };
  const auto range_start = [&](int rank) {
    return static_cast<std::int32_t>(static_cast<std::int64_t>(n) * rank / comm.size);
  };
  const std::int32_t first = range_start(comm.rank);
  const std::int32_t last = range_start(comm.rank + 1);
  std::vector<std::int32_t> local(static_cast<std::size_t>(last - first) * k);

  if (!scanner) {
    for (std::int32_t i = first; i < last; ++i)
      local[static_cast<std::size_t>(i - first)] = query_at(static_cast<std::size_t>(i));
  } else {
    const FeatureTwins twins(features, layout);
    const std::int32_t tasks = (last - first + kQueriesPerTask - 1) / kQueriesPerTask;
    Progress progress(comm.size > 1 ? "similarity sets (rank 0's share)" : "similarity sets",
                      last - first, "voxels");
    std::atomic<std::int64_t> done{0};
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int32_t task = 0; task < tasks; ++task) {
      const std::int32_t begin = first + task * kQueriesPerTask;
      const std::int32_t end = std::min(last, begin + kQueriesPerTask);
      // A query with k - 1 twins outside the windows has its set: they come first. The others
      // are searched.
      std::vector<std::int32_t> searched, searched_at;
      for (std::int32_t i = begin; i < end; ++i) {
        const std::int32_t query = query_at(static_cast<std::size_t>(i));
        std::int32_t* out = local.data() + static_cast<std::size_t>(i - first) * k;
        if (select_candidates(query, twins.of(query), windows, k, out) < k) {
          searched.push_back(query);
          searched_at.push_back(i);
        }
      }
      const auto lists = searched.empty() ? std::vector<std::vector<RankedVoxel>>()
                                          : scanner->shortlists(searched);
      for (std::size_t q = 0; q < searched.size(); ++q) {
        std::int32_t* out = local.data() + static_cast<std::size_t>(searched_at[q] - first) * k;
        repeat_last(select_candidates(searched[q],
                                      lists[q] | std::views::transform(&RankedVoxel::voxel),
                                      windows, k, out),
                    k, out);
      }
      const std::int64_t finished = done += end - begin;
      if (omp_get_thread_num() == 0)
        progress.update(finished);
    }
    progress.update(done);
    progress.finish();
  }

  // The ranks' ranges in query order, then each node's ranks put a share of them in voxel order
  // (share [begin, end) of the elements: the queries begin / k to end / k).
  const auto by_position = par::NodeSharedArray<std::int32_t>::concatenate(layout, local);
  const auto kk = static_cast<std::size_t>(k);
  SimilaritySets sets{features.dims(), k,
                      par::NodeSharedArray<std::int32_t>::filled(
                          layout, voxels * kk,
                          [&](std::span<std::int32_t> all, std::size_t begin, std::size_t end) {
                            for (std::size_t i = begin / kk; i < end / kk; ++i)
                              std::copy_n(by_position.begin() + i * kk, k,
                                          all.begin() +
                                              static_cast<std::ptrdiff_t>(query_at(i)) * k);
                          })};
  return sets;
}

} // namespace texsim::pipelines::solid_synthesis
