#pragma once
/// surface_synthesis: Wei & Levoy, "Texture Synthesis over Arbitrary Manifold Surfaces" (SIGGRAPH
/// 2001). The surface is retiled into a mesh pyramid (Turk's retiling of simplified copies), each
/// level gets a texture orientation (random, a user field, or n-way relaxation), each vertex a
/// neighbourhood flattened and resampled from the mesh, and the levels are synthesised coarse to
/// fine in two passes by nearest-neighbourhood search in the exemplar (exhaustive, TSVQ, or an
/// exact pruned kd-tree search). Outputs: the levels as a ParaView series, the colour on the input
/// mesh, a texture atlas with an OBJ, optionally a displaced surface.
///
/// Stages: mesh, exemplar, hierarchy, orientation, stencils, synthesis, output, atlas.
#include "geom/mesh_memory.hpp"
#include "pipelines/pipeline.hpp"
#include "pipelines/surface_synthesis/surface_synthesis_settings.hpp"

namespace texsim::pipelines::surface_synthesis {

class SurfaceSynthesisPipeline : public Pipeline {
public:
  void configure(const ConfigSection& section, const RunSettings& run) override;
  void run(RunContext& ctx) override;
  /// The input mesh, the pyramid split over the ranks and the finest level gathered on rank 0,
  /// plus stencils of the owned vertices: about 2 KiB per finest vertex over the ranks; the
  /// exemplar tables are small.
  MemoryEstimate estimate_memory(int ranks) const override;

private:
  SurfaceSynthesisSettings settings_;
  std::uint64_t seed_ = 1;
};

} // namespace texsim::pipelines::surface_synthesis
