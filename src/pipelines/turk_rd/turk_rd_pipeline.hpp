#pragma once
/// turk_rd: Turk's reaction-diffusion on arbitrary surfaces (SIGGRAPH 1991): the surface is
/// re-tiled into evenly spread cells (relaxation + restricted Voronoi regions), a cascade of
/// reaction-diffusion systems runs on the cells (spots, stripes, user expressions; later systems
/// constrained by earlier patterns; frozen initiators; diffusion varying over the surface), and
/// the pattern is rendered onto the input mesh by Turk's weighted sum and as a bump map.
///
/// Stages: mesh, retiling, setup (series, checkpoint), steps (explicit steps of each cascade stage,
/// frames every output.every and checkpoints every checkpoint.every cumulative steps), finish
/// (metrics per stage).
#include "geom/mesh_memory.hpp"
#include "pipelines/pipeline.hpp"
#include "pipelines/turk_rd/turk_rd_settings.hpp"

namespace texsim::pipelines::turk_rd {

class TurkRdPipeline : public Pipeline {
public:
  void configure(const ConfigSection& section, const RunSettings& run) override;
  void run(RunContext& ctx) override;
  /// The whole mesh on rank 0 while it builds and splits it (the peak of the largest rank); each
  /// rank's share of the triangles, cells, couplings and frames divided among ranks (measured:
  /// 1.4 GiB peak for 1.3 million triangles and 20,000 cells at 1 rank, estimated 1.7 GiB).
  MemoryEstimate estimate_memory(int ranks) const override {
    return geom::estimate_mesh_memory(settings_.mesh, "turk_rd.mesh", ranks, 400, 1000);
  }

private:
  TurkRdSettings settings_;
};

} // namespace texsim::pipelines::turk_rd
