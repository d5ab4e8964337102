#pragma once
/// Checkpoints of the synthesis pyramid: the exemplar-coordinate volume S of a finished level,
/// written collectively by slab, so a killed job resumes at the next level with the same bytes.
#include "io/checkpoint_store.hpp"
#include "pipelines/solid_synthesis/coordinate_slab.hpp"

#include <string>

namespace texsim::pipelines::solid_synthesis {

/// Writes level `level(slab)` as checkpoint step `level`, tagged with the exemplar's content hash.
/// Collective.
void save_level(const par::Comm& comm, const io::CheckpointStore& store, const CoordinateSlab& slab,
                const std::string& exemplar_hash);

/// Reads the level stored in `reader` into a slab laid out for this rank. InputError naming the
/// file when it was written for another exemplar (same config, changed file contents) or holds
/// no level. Collective.
CoordinateSlab load_level(const par::Comm& comm, const io::CheckpointReader& reader,
                          const std::string& exemplar_hash);

} // namespace texsim::pipelines::solid_synthesis
