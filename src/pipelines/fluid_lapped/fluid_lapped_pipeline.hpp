#pragma once
/// fluid_lapped: Gagnon, Guzman, Mould and Paquette, "Patch Erosion for Deformable Lapped Textures
/// on 3D Fluids" (Eurographics 2021 short paper). Patches copied from the fluid surface at
/// Poisson-disk centres are flattened (LSCM), carried by the flow (RK4 advection, projection onto
/// each frame's surface), eroded where they are distorted, near their boundary and where the
/// exemplar's feature map is low, and composited into each frame's texture atlas as lapped
/// textures, oldest on top, with no blending; texels no patch covers get new patches below the
/// others, and patches that win no texel go.
///
/// Stages: exemplar, frames, advection, update (projection, dropping, weights), create
/// (compositing and new patches), output, checkpoint.
#include "pipelines/fluid_lapped/fluid_lapped_settings.hpp"
#include "pipelines/pipeline.hpp"

namespace texsim::pipelines::fluid_lapped {

class FluidLappedPipeline : public Pipeline {
public:
  void configure(const ConfigSection& section, const RunSettings& run) override;
  void run(RunContext& ctx) override;
  std::vector<std::string> run_length_keys() const override {
    return {"fluid_lapped.frames.count"};
  }
  /// Per rank: the frame mesh and its atlas map (replicated), the rank's atlas tiles (16 bytes a
  /// texel) and the gathered atlas on the rank that writes the frame's images.
  MemoryEstimate estimate_memory(int ranks) const override;

private:
  FluidLappedSettings settings_;
};

} // namespace texsim::pipelines::fluid_lapped
