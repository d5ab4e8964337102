#include "pipelines/solid_synthesis/synthesis_exemplar.hpp"

#include "core/error.hpp"

#include <algorithm>

namespace texsim::pipelines::solid_synthesis {

std::vector<int> corrected_stack_levels(const AppearanceSpace& space, int pyramid_levels) {
  std::vector<int> levels;
  const int coarsest = static_cast<int>(space.levels.size()) - 1;
  for (int s = 0; s <= std::min(pyramid_levels, coarsest - 1); ++s)
    levels.push_back(s);
  return levels;
}

SynthesisExemplar make_synthesis_exemplar(const AppearanceSpace& space,
                                          const std::vector<SimilaritySets>& sets) {
  TEXSIM_VERIFY(sets.size() == space.levels.size(), "one similarity-set slot per stack level");
  SynthesisExemplar exemplar{space.colours.dims(), {}, {}};
  for (std::size_t s = 0; s < space.levels.size(); ++s) {
    exemplar.features.push_back(&space.levels[s].features);
    exemplar.sets.push_back(sets[s].candidates.empty() ? nullptr : &sets[s]);
  }
  return exemplar;
}

} // namespace texsim::pipelines::solid_synthesis
