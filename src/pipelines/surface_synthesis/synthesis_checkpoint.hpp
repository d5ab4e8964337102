#pragma once
/// Saving and restoring a surface_synthesis run between two colour classes: the colours and
/// chosen pixels of every level by vertex id, where the synthesis stands (level, pass, next
/// class), and hashes of the exemplar pyramid and of the mesh hierarchy, so a checkpoint written at
/// one rank count resumes at any other and a checkpoint of other inputs is refused.
#include "io/checkpoint_store.hpp"
#include "pipelines/surface_synthesis/level_synthesizer.hpp"
#include "pipelines/surface_synthesis/mesh_pyramid.hpp"

#include <string>
#include <vector>

namespace texsim::pipelines::surface_synthesis {

/// Where a run stands: the next class to synthesise.
struct SynthesisPosition {
  int level = 0; ///< pyramid level (0 = finest)
  Pass pass = Pass::extrapolate;
  std::int32_t next_class = 0;
};

struct SynthesisIdentity {
  std::string exemplar_hash;
  std::string hierarchy_hash;
};

/// Writes checkpoint `step` (classes finished so far). Each rank writes its owned run of every
/// level. Collective.
void save_synthesis(const par::Comm& comm, const io::CheckpointStore& store, std::int64_t step,
                    const std::vector<RetiledLevel>& pyramid,
                    const std::vector<LevelColours>& colours, const SynthesisPosition& position,
                    const SynthesisIdentity& identity);

/// Reads this rank's run of every level's colours and the position. Throws InputError
/// naming the file when the hierarchy, the exemplar or a level's size does not match. Collective.
SynthesisPosition load_synthesis(const par::Comm& comm, const io::CheckpointReader& reader,
                                 const std::vector<RetiledLevel>& pyramid,
                                 const SynthesisIdentity& identity,
                                 std::vector<LevelColours>& colours);

/// Hash of the retiled levels: fnv1a64 of their mesh_hash values (each the hash of a level's
/// positions and triangles), level 0 first.
std::string hierarchy_hash(const std::vector<RetiledLevel>& pyramid);

} // namespace texsim::pipelines::surface_synthesis
