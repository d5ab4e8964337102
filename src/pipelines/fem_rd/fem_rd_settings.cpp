#include "pipelines/fem_rd/fem_rd_settings.hpp"

namespace texsim::pipelines::fem_rd {

FemRdSettings read_fem_rd_settings(const ConfigSection& section) {
  FemRdSettings settings;
  settings.mesh = geom::read_mesh_source(section.section("mesh"));
  settings.partition = section.choice<geom::PartitionMethod>(
      "partition", settings.partition,
      {{"scotch", geom::PartitionMethod::kScotch}, {"morton", geom::PartitionMethod::kMorton}});

  settings.rd.basis = section.choice<FemBasis>("basis", settings.rd.basis,
                                               {{"p1", FemBasis::kP1}, {"loop", FemBasis::kLoop}});
  const auto time = section.section("time");
  settings.steps = time.get<int>("steps", settings.steps, non_negative_int());
  settings.rd.dt = time.get<double>("dt", settings.rd.dt, positive());
  settings.rd.lumped_mass =
      section.choice<bool>("mass", false, {{"consistent", false}, {"lumped", true}});
  const auto solver = section.section("solver");
  settings.rd.rtol = solver.get<double>("rtol", settings.rd.rtol, in_range(1e-15, 0.1));
  settings.rd.preconditioner =
      solver.choice<RdPreconditioner>("preconditioner", settings.rd.preconditioner,
                                      {{"auto", RdPreconditioner::kAuto},
                                       {"jacobi", RdPreconditioner::kJacobi},
                                       {"gamg", RdPreconditioner::kGamg},
                                       {"boomeramg", RdPreconditioner::kBoomerAmg}});
  settings.diffusion = read_diffusion_field(section, settings.mesh);

  const auto smoothing = section.section("smoothing");
  settings.smoothing = smoothing.get<bool>("enabled", false);
  auto& smoother = settings.smoother;
  smoother.dt = smoothing.get<double>("dt", smoother.dt, positive());
  smoother.feature.lambda = smoothing.get<double>("lambda", smoother.feature.lambda, positive());
  smoother.feature.alpha = smoothing.get<double>("alpha", smoother.feature.alpha, non_negative());
  smoother.feature.beta = smoothing.get<double>("beta", smoother.feature.beta, non_negative());
  smoother.feature.damp_normal_component =
      smoothing.get<bool>("damp_normal", smoother.feature.damp_normal_component);
  smoother.mu = smoothing.get<double>("mu", smoother.mu, in_range(0.0, 1.0));
  smoother.isotropic = smoothing.get<bool>("isotropic", smoother.isotropic);
  settings.smooth_functions = smoothing.get<bool>("functions", settings.smooth_functions);
  smoother.function_lambda =
      smoothing.get<double>("function_lambda", smoother.function_lambda, positive());
  smoother.lumped_mass = settings.rd.lumped_mass;
  smoother.rtol = settings.rd.rtol;
  settings.smoothing_every = smoothing.get<int>("every", settings.smoothing_every, positive_int());
  settings.smoothing_steps =
      smoothing.get<int>("steps", settings.smoothing_steps, non_negative_int());
  settings.rebuild_every =
      smoothing.get<int>("rebuild_every", settings.rebuild_every, positive_int());
  return settings;
}

} // namespace texsim::pipelines::fem_rd
