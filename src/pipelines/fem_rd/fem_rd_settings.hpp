#pragma once
/// The `fem_rd:` section of a config.
#include "core/config.hpp"
#include "geom/distributed_mesh.hpp"
#include "geom/mesh_source.hpp"
#include "pipelines/fem_rd/geometry_smoother.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"

namespace texsim::pipelines::fem_rd {

struct FemRdSettings {
  geom::MeshSource mesh;                                            ///< fem_rd.mesh
  geom::PartitionMethod partition = geom::PartitionMethod::kScotch; ///< fem_rd.partition
  int steps = 1000;                                                 ///< fem_rd.time.steps
  RdOptions rd; ///< fem_rd.time.dt, fem_rd.mass, fem_rd.solver.{rtol, preconditioner}
  std::optional<DiffusionFieldSettings> diffusion; ///< fem_rd.diffusion
  bool smoothing = false;
  bool smooth_functions = false; ///< fem_rd.smoothing.functions: also smooth every species    ///<
                                 ///< fem_rd.smoothing.enabled
  SmoothingOptions smoother;     ///< fem_rd.smoothing.{dt, lambda, alpha, beta, mu, isotropic}
  int smoothing_every = 1;       ///< fem_rd.smoothing.every: RD steps per smoothing step
  int smoothing_steps = 100;     ///< fem_rd.smoothing.steps: smoothing steps in all
  int rebuild_every = 10;        ///< fem_rd.smoothing.rebuild_every: RD steps between rebuilds of
                                 ///< the RD matrices on the moved surface
};

/// Reads and validates the section; the model section is validated by building the model.
FemRdSettings read_fem_rd_settings(const ConfigSection& section);

} // namespace texsim::pipelines::fem_rd
