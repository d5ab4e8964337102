#pragma once
/// Which exemplar levels a synthesis needs, and the view of them the synthesizer reads.
#include "pipelines/solid_synthesis/appearance_space.hpp"
#include "pipelines/solid_synthesis/pyramid_synthesizer.hpp"
#include "pipelines/solid_synthesis/similarity_sets.hpp"

#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// Stack levels a pyramid of `pyramid_levels` + 1 levels corrects: log2 h_l for each level,
/// except the coarsest stack level (the exemplar mean, where every candidate ties). These are the
/// levels that need similarity sets.
std::vector<int> corrected_stack_levels(const AppearanceSpace& space, int pyramid_levels);

/// Features of every stack level of `space`, with `sets[s]` where it was computed (empty sets:
/// level s is not corrected). Points into `space` and `sets`, which must outlive it.
SynthesisExemplar make_synthesis_exemplar(const AppearanceSpace& space,
                                          const std::vector<SimilaritySets>& sets);

} // namespace texsim::pipelines::solid_synthesis
