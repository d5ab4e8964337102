#pragma once
/// Keeping the surface covered (section 5.1 and issue item 6): the patches are composited into the
/// frame's atlas, then every texel no patch covers gets a new full-size patch at its surface
/// point, below all others, in the paper's order (the first uncovered texel in atlas order; later
/// texels see it), and patches that win no texel are removed.
#include "par/comm.hpp"
#include "pipelines/fluid_lapped/atlas_compositor.hpp"
#include "pipelines/fluid_lapped/frame_surface.hpp"
#include "pipelines/fluid_lapped/patch_checkpoint.hpp"

#include <cstdint>

namespace texsim::pipelines::fluid_lapped {

struct PopulationSettings {
  double radius = 0;      ///< patch radius r
  double delta_max = 3.0; ///< of the new patches' weights
  int batch = 64;         ///< candidates built per round (independent of the rank count)
  std::uint64_t seed = 1; ///< keys the patches' rotations
};

/// What covering one frame did.
struct PopulationReport {
  std::int64_t created = 0;  ///< new patches accepted
  std::int64_t rejected = 0; ///< candidates built but not accepted (their texel was covered)
  std::int64_t removed = 0;  ///< patches that won no texel
  std::int64_t patches = 0;  ///< patches after the frame
  int rounds = 0;            ///< candidate rounds
};

/// After `state.patches` (this rank's, any split) were composited into `compositor`, adds
/// patches until every used texel is covered or unreachable, and drops the patches that won no
/// texel. The paper's order exactly: a round walks the first uncovered texels in atlas order,
/// skips those an accepted new patch covers, builds candidates for the next `batch` of the rest
/// (candidate i on rank i mod size, id next_id + i, which lists the round's texels it covers:
/// only those lists travel, and an accepted patch stays on the rank that built it), and accepts
/// them in texel order, dropping a candidate whose texel an earlier one covers. Texels close to
/// an earlier pick of the batch are deferred instead of picked; one that turns out uncovered ends
/// the batch, so the accepted patches are those of the one-texel-at-a-time walk. Ids of dropped
/// candidates are skipped, so ids never depend on the rank count. A texel whose own new patch
/// does not cover it (its centre triangle rejected) is marked unreachable instead of looping.
/// Collective.
PopulationReport populate_frame(const par::Comm& comm, const FrameSurface& frame,
                                AtlasCompositor& compositor, PatchState& state,
                                const PopulationSettings& settings);

} // namespace texsim::pipelines::fluid_lapped
