#pragma once
/// The memory per rank a solid synthesis run needs, from its settings alone.
#include "core/memory_budget.hpp"
#include "pipelines/solid_synthesis/solid_synthesis_settings.hpp"

namespace texsim::pipelines::solid_synthesis {

/// The sum of two terms, naming the key of the larger. Exemplar: its Gaussian stack, one full-size
/// level per octave, with colours per voxel on every rank, appearance features and similarity sets
/// per voxel once per node (MemoryEstimate::node_shared_bytes); the voxel
/// count of a file exemplar is taken from its size (4 bytes per voxel). Synthesis: the pyramid
/// (next power of two of the largest edge, cubed) divided among ranks, plus the result gathered on
/// rank 0 for the .vdb/.vti writers. Names exemplar.size, exemplar.file, synthesis.size or
/// synthesis.dims (measured: 255 MiB peak RSS for a 128^3 result from a 16^3 exemplar at 1 rank,
/// 226 MiB estimated, 354 MiB with app/preflight's allowance for the libraries). Serial.
MemoryEstimate estimate_solid_synthesis_memory(const SolidSynthesisSettings& settings, int ranks);

} // namespace texsim::pipelines::solid_synthesis
