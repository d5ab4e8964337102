#pragma once
/// fem_rd: Galerkin FEM reaction-diffusion on a triangle surface coupled with feature-preserving
/// geometric diffusion (Bajaj, Zhang, Xu), distributed with PETSc.
///
/// Stages: mesh (build, Loop-refine, perturb, partition), setup (matrices, initial state, or a
/// checkpoint), steps (optional smoothing step of the surface, rebuild of the RD matrices on the
/// moved surface every `rebuild_every` steps, one semi-implicit step of every species; frames every
/// output.every steps and checkpoints every checkpoint.every steps), finish (metrics).
#include "geom/mesh_memory.hpp"
#include "pipelines/fem_rd/fem_rd_settings.hpp"
#include "pipelines/pipeline.hpp"
#include "rd/reaction_model.hpp"

#include <memory>

namespace texsim::pipelines::fem_rd {

class FemRdPipeline : public Pipeline {
public:
  void configure(const ConfigSection& section, const RunSettings& run) override;
  void run(RunContext& ctx) override;
  std::vector<std::string> run_length_keys() const override { return {"fem_rd.time.steps"}; }
  /// The whole mesh on every rank; matrices, vectors and smoothing state divided among ranks
  /// (measured: 1.05 GiB peak for 1.3 million triangles at 1 rank, estimated 1.3 GiB).
  MemoryEstimate estimate_memory(int ranks) const override {
    // Measured on a level-9 icosphere (5.2 M triangles, 2 steps with smoothing): about 2,000
    // bytes per triangle divided among the ranks (the part, its halo, the solvers); rank 0 also
    // holds the whole surface while it builds and cuts it (counted at 200 bytes per triangle).
    // The Loop basis couples 12 or more functions per triangle and keeps 16 quadrature points'
    // geometry: measured 5,300 bytes per triangle more (level-6 icosphere, 1 rank).
    const std::uint64_t per_triangle = settings_.rd.basis == FemBasis::kLoop ? 7300 : 2000;
    return geom::estimate_mesh_memory(settings_.mesh, "fem_rd.mesh", ranks, 200, per_triangle);
  }

private:
  FemRdSettings settings_;
  std::unique_ptr<rd::ReactionModel> model_;
};

} // namespace texsim::pipelines::fem_rd
