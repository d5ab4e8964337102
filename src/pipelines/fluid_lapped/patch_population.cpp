#include "pipelines/fluid_lapped/patch_population.hpp"

#include "par/collective.hpp"
#include "pipelines/fluid_lapped/patch_builder.hpp"
#include "pipelines/fluid_lapped/patch_distortion.hpp"
#include "pipelines/fluid_lapped/patch_exchange.hpp"

#include <mpi.h>

#include <algorithm>

namespace texsim::pipelines::fluid_lapped {

PopulationReport populate_frame(const par::Comm& comm, const FrameSurface& frame,
                                AtlasCompositor& compositor, PatchState& state,
                                const PopulationSettings& settings) {
  PopulationReport report;
  for (;;) {
    const auto uncovered = compositor.first_uncovered(std::size_t(settings.batch));
    if (uncovered.empty())
      break;
    ++report.rounds;
    std::vector<Patch> built;
    par::run_collectively(comm, [&] {
      for (std::size_t i = std::size_t(comm.rank); i < uncovered.size();
           i += std::size_t(comm.size)) {
        auto patch = build_patch(frame, uncovered[i].point, settings.radius,
                                 state.next_id + std::int64_t(i), state.frame + 1, settings.seed);
        update_weights(patch, settings.radius, settings.delta_max);
        built.push_back(std::move(patch));
      }
    });
    const auto candidates = allgather_patches(comm, built); // sorted by id = texel order
    std::vector<const Patch*> accepted;
    for (const auto& candidate : candidates) {
      const auto& texel = uncovered[std::size_t(candidate.id - state.next_id)];
      const bool covered = std::any_of(accepted.begin(), accepted.end(), [&](const Patch* p) {
        return compositor.patch_sample(*p, texel).has_value();
      });
      if (covered) {
        ++report.rejected;
      } else if (!compositor.patch_sample(candidate, texel)) {
        compositor.mark_unreachable(texel.x, texel.y);
        ++report.rejected;
      } else {
        accepted.push_back(&candidate);
      }
    }
    state.next_id += std::int64_t(uncovered.size());
    report.created += std::int64_t(accepted.size());
    std::vector<Patch> mine;
    for (std::size_t j = std::size_t(comm.rank); j < accepted.size(); j += std::size_t(comm.size))
      mine.push_back(*accepted[j]);
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
