#include "pipelines/fluid_lapped/patch_population.hpp"

#include "par/collective.hpp"
#include "par/record_exchange.hpp"
#include "pipelines/fluid_lapped/patch_builder.hpp"
#include "pipelines/fluid_lapped/patch_distortion.hpp"

#include <mpi.h>

#include <algorithm>
#include <tuple>

namespace texsim::pipelines::fluid_lapped {
namespace {

/// Uncovered texels fetched at once: the round walks them in order and asks for more only when
/// they are used up.
constexpr std::size_t kTexelsPerRound = 4096;

/// That candidate `patch` covers texel `texel` of the round (a position in its texel list).
struct Cover {
  std::int64_t patch;
  std::int32_t texel;
};

/// One texel of a batch's walk: picked for a candidate, or deferred to an earlier pick.
struct BatchTexel {
  std::int32_t position; ///< in the round's texel list
  bool deferred;
};

/// That a new patch at `pick` will likely cover `texel`: their surface points lie within `near`
/// (the patch's reach) and their triangles face the same side (a patch takes only those). A wrong
/// guess costs candidates, never exactness (populate_frame ends the batch there).
bool likely_covers(const FrameSurface& frame, const UncoveredTexel& pick,
                   const UncoveredTexel& texel, double near) {
  return (pick.point.position - texel.point.position).squaredNorm() < near * near &&
         frame.triangle_normals[std::size_t(pick.point.triangle)].dot(
             frame.triangle_normals[std::size_t(texel.point.triangle)]) > 0;
}

} // namespace

PopulationReport populate_frame(const par::Comm& comm, const FrameSurface& frame,
                                AtlasCompositor& compositor, PatchState& state,
                                const PopulationSettings& settings) {
  PopulationReport report;
  for (;;) {
    const auto uncovered = compositor.first_uncovered(kTexelsPerRound);
    if (uncovered.empty())
      break;
    ++report.rounds;
    const UncoveredTexelIndex index(uncovered);
    std::vector<char> covered(uncovered.size(), 0); // by a patch accepted in this round
    std::vector<Patch> accepted;                    // this rank's
    std::size_t next = 0;
    while (next < uncovered.size()) {
      // The next texels no accepted patch covers: the paper's "first uncovered texel", a batch
      // at a time, candidate i built by rank i mod size, which also lists the round's texels the
      // candidate covers. Only those lists travel, so acceptance costs every rank little.
      // A texel near an earlier pick of the batch (within r, facing its side) is deferred, not
      // picked: that pick's patch will likely cover it, and consecutive texels of a row would
      // otherwise fill the batch with candidates that cover one another (measured on the large
      // dam break: 30 dropped candidates per accepted patch without deferral, 10 at r/2, 6 at r).
      std::vector<BatchTexel> walk;
      std::vector<std::int32_t> picks;
      while (next < uncovered.size() && picks.size() < std::size_t(settings.batch)) {
        const auto position = std::int32_t(next++);
        if (covered[std::size_t(position)])
          continue;
        const bool deferred = std::any_of(picks.begin(), picks.end(), [&](std::int32_t pick) {
          return likely_covers(frame, uncovered[std::size_t(pick)],
                               uncovered[std::size_t(position)], settings.radius);
        });
        walk.push_back({position, deferred});
        if (!deferred)
          picks.push_back(position);
      }
      if (picks.empty())
        break;
      const auto first_id = state.next_id;
      state.next_id += std::int64_t(picks.size());
      std::vector<Patch> built;
      std::vector<Cover> covers;
      par::run_collectively(comm, [&] {
        for (std::size_t i = std::size_t(comm.rank); i < picks.size();
             i += std::size_t(comm.size)) {
          const auto& texel = uncovered[std::size_t(picks[i])];
          auto patch = build_patch(frame, texel.point, settings.radius, first_id + std::int64_t(i),
                                   state.frame + 1, settings.seed,
                                   created_patch_rotation_key(state.frame + 1, texel.x, texel.y));
          update_weights(patch, settings.radius, settings.delta_max);
          // Texels before its own matter no more: they come before every later pick.
          for (const auto position :
               compositor.covered_texels(compositor.image_of(patch), index, picks[i]))
            covers.push_back({patch.id, position});
          built.push_back(std::move(patch));
        }
      });
      auto all_covers = par::allgather_records(comm, covers);
      std::sort(all_covers.begin(), all_covers.end(), [](const Cover& a, const Cover& b) {
        return std::tie(a.patch, a.texel) < std::tie(b.patch, b.texel);
      });
      // Accept in texel order: a candidate whose texel an earlier one covers is dropped. A
      // deferred texel that no accepted patch covers after all ends the batch there: the later
      // candidates are dropped and the walk resumes at that texel, so the patches accepted are
      // those of the one-texel-at-a-time order.
      auto from = all_covers.begin();
      std::size_t i = 0;
      for (const auto& step : walk) {
        if (step.deferred) {
          if (covered[std::size_t(step.position)])
            continue;
          next = std::size_t(step.position);
          report.rejected += std::int64_t(picks.size() - i);
          break;
        }
        const auto id = first_id + std::int64_t(i);
        const auto to =
            std::find_if(from, all_covers.end(), [&](const Cover& c) { return c.patch != id; });
        const auto texel = step.position;
        if (covered[std::size_t(texel)]) {
          ++report.rejected;
        } else if (std::none_of(from, to, [&](const Cover& c) { return c.texel == texel; })) {
          const auto& missed = uncovered[std::size_t(texel)];
          compositor.mark_unreachable(missed.x, missed.y);
          ++report.rejected;
        } else {
          for (auto c = from; c != to; ++c)
            covered[std::size_t(c->texel)] = 1;
          ++report.created;
          if (i % std::size_t(comm.size) == std::size_t(comm.rank))
            accepted.push_back(std::move(built[i / std::size_t(comm.size)]));
        }
        from = to;
        ++i;
      }
    }
    compositor.composite(accepted);
    for (auto& patch : accepted)
      state.patches.push_back(std::move(patch));
  }
  const auto winners = compositor.winning_patches();
  const auto before = std::int64_t(state.patches.size());
  std::erase_if(state.patches, [&](const Patch& patch) {
    return !std::binary_search(winners.begin(), winners.end(), patch.id);
  });
  std::sort(state.patches.begin(), state.patches.end(),
            [](const Patch& a, const Patch& b) { return a.id < b.id; });
  std::int64_t local_removed = before - std::int64_t(state.patches.size());
  MPI_Allreduce(&local_removed, &report.removed, 1, MPI_INT64_T, MPI_SUM, comm.raw);
  report.patches = std::int64_t(winners.size());
  return report;
}

} // namespace texsim::pipelines::fluid_lapped
