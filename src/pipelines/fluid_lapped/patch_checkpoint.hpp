#pragma once
/// Checkpoints of fluid_lapped: after a frame, the whole patch set as ragged arrays in id order
/// (per patch: id, birth frame, vertex and triangle counts; per vertex: position, frame triangle,
/// rest uv, weight; per triangle: patch-local corners), the next patch id and the frame. Written in
/// id order, so the file is the same for any rank count and a restart may use another one.
#include "io/checkpoint_reader.hpp"
#include "io/checkpoint_store.hpp"
#include "par/comm.hpp"
#include "pipelines/fluid_lapped/patch.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace texsim::pipelines::fluid_lapped {

/// Where the run stands after a finished frame.
struct PatchState {
  std::vector<Patch> patches; ///< this rank's patches, sorted by id
  std::int64_t next_id = 0;   ///< id of the next patch to be created
  std::int32_t frame = -1;    ///< the last finished frame
};

/// Writes `state` (any split of the patches over ranks) as checkpoint step state.frame + 1, with
/// `inputs_hash` (the frames and exemplar it was computed from). Collective.
void save_patch_state(const par::Comm& comm, const io::CheckpointStore& store,
                      const PatchState& state, const std::string& inputs_hash);

/// Reads a checkpoint written by save_patch_state at any rank count: this rank gets a contiguous
/// run of the patches in id order. Throws InputError naming the file when it was written for
/// other inputs. Collective.
PatchState load_patch_state(const par::Comm& comm, const io::CheckpointReader& reader,
                            const std::string& inputs_hash);

} // namespace texsim::pipelines::fluid_lapped
