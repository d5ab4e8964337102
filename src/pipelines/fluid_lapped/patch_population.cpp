#include "pipelines/fluid_lapped/patch_population.hpp"

#include "par/collective.hpp"
#include "pipelines/fluid_lapped/patch_builder.hpp"
#include "pipelines/fluid_lapped/patch_distortion.hpp"
#include "pipelines/fluid_lapped/patch_exchange.hpp"

#include <mpi.h>

#include <algorithm>

namespace texsim::pipelines::fluid_lapped {
namespace {

/// A patch accepted in this round, drawn into the atlas once for the many texels it is asked
/// about.
struct Accepted {
  const Patch* patch;
  PatchImage image;
};

/// Uncovered texels fetched at once: the round walks them in order and asks for more only when
/// they are used up.
constexpr std::size_t kTexelsPerRound = 4096;

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
    std::vector<Patch> candidates; // every rank's, in texel order: kept until composited
    std::vector<Accepted> accepted;
    const auto covered = [&](const UncoveredTexel& texel) {
      return std::any_of(accepted.begin(), accepted.end(), [&](const Accepted& a) {
        return compositor.patch_sample(a.image, texel).has_value();
      });
    };
    std::vector<std::vector<Patch>> batches;
    std::size_t next = 0;
    while (next < uncovered.size()) {
      // The next texels no accepted patch covers: the paper's "first uncovered texel", a batch
      // at a time, each built by rank i mod size.
      std::vector<const UncoveredTexel*> picks;
      while (next < uncovered.size() && picks.size() < std::size_t(settings.batch)) {
        const auto& texel = uncovered[next++];
        if (!covered(texel))
          picks.push_back(&texel);
      }
      if (picks.empty())
        break;
      std::vector<Patch> built;
      par::run_collectively(comm, [&] {
        for (std::size_t i = std::size_t(comm.rank); i < picks.size();
             i += std::size_t(comm.size)) {
          auto patch = build_patch(frame, picks[i]->point, settings.radius,
                                   state.next_id + std::int64_t(i), state.frame + 1, settings.seed);
          update_weights(patch, settings.radius, settings.delta_max);
          built.push_back(std::move(patch));
        }
      });
      batches.push_back(allgather_patches(comm, built)); // sorted by id = texel order
      const auto first_id = state.next_id;
      state.next_id += std::int64_t(picks.size());
      // Accept in texel order: a candidate whose texel an earlier one covers is dropped.
      for (const auto& candidate : batches.back()) {
        const auto& texel = *picks[std::size_t(candidate.id - first_id)];
        if (covered(texel)) {
          ++report.rejected;
        } else if (auto image = compositor.image_of(candidate);
                   !compositor.patch_sample(image, texel)) {
          compositor.mark_unreachable(texel.x, texel.y);
          ++report.rejected;
        } else {
          accepted.push_back({&candidate, std::move(image)});
        }
      }
    }
    report.created += std::int64_t(accepted.size());
    std::vector<Patch> mine;
    for (std::size_t j = std::size_t(comm.rank); j < accepted.size(); j += std::size_t(comm.size))
      mine.push_back(*accepted[j].patch);
    compositor.composite(mine);
    for (auto& patch : mine)
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
