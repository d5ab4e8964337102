#pragma once
/// solid_synthesis: solid texture synthesis from a volume exemplar with vector-field control (Su
/// 2008, chapters 3-5). Exemplar -> Gaussian stack -> appearance-space features (PCA of 5^3
/// neighbourhoods) -> exact k-coherence similarity sets (cached) -> pyramid synthesis with
/// per-level checkpoints -> .vdb/.vti volumes, PNG cross-sections and quality metrics.
#include "pipelines/pipeline.hpp"
#include "pipelines/solid_synthesis/memory_estimate.hpp"
#include "pipelines/solid_synthesis/solid_synthesis_settings.hpp"

namespace texsim::pipelines::solid_synthesis {

class SolidSynthesisPipeline : public Pipeline {
public:
  void configure(const ConfigSection& section, const RunSettings& run) override;
  void run(RunContext& ctx) override;
  MemoryEstimate estimate_memory(int ranks) const override {
    return estimate_solid_synthesis_memory(settings_, ranks);
  }

private:
  SolidSynthesisSettings settings_;
};

} // namespace texsim::pipelines::solid_synthesis
