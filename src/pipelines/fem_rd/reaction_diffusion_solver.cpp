#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/rng.hpp"
#include "geom/distributed_measures.hpp"
#include "geom/loop_patch_basis.hpp"
#include "par/collective.hpp"
#include "par/petsc_session.hpp"
#include "pipelines/fem_rd/loop_assembler.hpp"
#include "pipelines/fem_rd/p1_assembler.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace texsim::pipelines::fem_rd {
namespace {
/// CounterRng stream of the probe's right-hand side.
constexpr std::uint32_t kProbeStream = 0x7e57;

std::unique_ptr<FemAssembler> make_assembler(const geom::DistributedMesh& mesh, FemBasis basis) {
  if (basis == FemBasis::kLoop)
    return std::make_unique<LoopAssembler>(mesh);
  return std::make_unique<P1Assembler>(mesh);
}
} // namespace

ReactionDiffusionSolver::ReactionDiffusionSolver(const par::Comm& comm,
                                                 const geom::DistributedMesh& mesh,
                                                 const rd::ReactionModel& model,
                                                 const RdOptions& options,
                                                 const std::optional<DiffusionFieldSettings>& field)
    : comm_(comm), mesh_(mesh), model_(model), options_(options),
      assembler_(make_assembler(mesh, options.basis)), names_(model.species()) {
  if (field)
    field_ = std::make_unique<DiffusionField>(*field, names_);
  mass_ = assembler_->create_matrix(comm);
  for (std::size_t s = 0; s < names_.size(); ++s) {
    fields_.push_back(
        std::make_unique<par::GhostedVector>(comm, mesh.owned_count(), mesh.ghosts()));
    systems_.push_back(assembler_->create_matrix(comm));
  }
  TEXSIM_PETSC_CALL(MatCreateVecs(mass_, ones_.address(), rhs_.address()));
  TEXSIM_PETSC_CALL(VecDuplicate(rhs_, explicit_part_.address()));
  TEXSIM_PETSC_CALL(VecSet(ones_, 1.0));
  rebuild_geometry();

  const auto initial = model.initial_state(rd::VertexData{local_ids_, local_xyz_});
  TEXSIM_VERIFY(initial.size() == names_.size(), "model gave " << initial.size()
                                                               << " initial fields for "
                                                               << names_.size() << " species");
  for (std::size_t s = 0; s < names_.size(); ++s)
    fields_[s]->set_owned(std::span(initial[s]).first(mesh.owned_count()));

  diffusion_ = species_diffusion();
  log::info(log::cat("fem_rd: basis ", assembler_->description(), " on rank 0"));
  preconditioner_ = choose_preconditioner();
  for (std::size_t s = 0; s < names_.size(); ++s)
    solvers_.push_back(std::make_unique<par::CgSolver>(comm, options.rtol, preconditioner_));
  if (preconditioner_ != par::Preconditioner::kJacobi) {
    for (std::size_t s = 0; s < names_.size(); ++s)
      preconditioning_.push_back(assembler_->create_matrix(comm));
    assemble_preconditioners();
  }
}

std::vector<std::span<const double>> ReactionDiffusionSolver::coefficient_state() {
  std::vector<std::span<const double>> state;
  const std::int32_t count = assembler_->coefficient_count();
  if (count == mesh_.local_count()) {
    for (const auto& field : fields_)
      state.push_back(field->local());
    return state;
  }
  halo_state_.resize(fields_.size());
  for (std::size_t s = 0; s < fields_.size(); ++s) {
    halo_state_[s] = on_whole_halo(s);
    state.push_back(halo_state_[s]);
  }
  return state;
}

std::vector<double> ReactionDiffusionSolver::on_whole_halo(std::size_t s) const {
  const auto local = fields_[s]->local();
  std::vector<double> values(std::size_t(mesh_.mesh().num_vertices()), 0.0);
  std::copy(local.begin(), local.end(), values.begin());
  mesh_.update_halo(values);
  return values;
}

std::vector<double> ReactionDiffusionSolver::surface_values(std::size_t s) const {
  const auto local = fields_[s]->local();
  if (options_.basis == FemBasis::kP1)
    return {local.begin(), local.end()};
  const std::vector<double> coefficients = on_whole_halo(s);
  const geom::LoopPatchBasis basis(mesh_.mesh(), mesh_.topology(), mesh_.creases());
  std::vector<double> values(local.size());
  for (std::int32_t v = 0; v < mesh_.local_count(); ++v)
    basis.limit_value(v, coefficients, 1, std::span(values).subspan(std::size_t(v), 1));
  return values;
}

std::vector<geom::Vec3> ReactionDiffusionSolver::surface_points() const {
  const auto& positions = mesh_.mesh().positions;
  std::vector<geom::Vec3> points(positions.begin(), positions.begin() + mesh_.local_count());
  if (options_.basis == FemBasis::kP1)
    return points;
  const geom::LoopPatchBasis basis(mesh_.mesh(), mesh_.topology(), mesh_.creases());
  const std::span<const double> xyz(positions.front().data(), 3 * positions.size());
  for (std::int32_t v = 0; v < mesh_.local_count(); ++v)
    basis.limit_value(v, xyz, 3, std::span(points[std::size_t(v)].data(), 3));
  return points;
}

std::vector<double> ReactionDiffusionSolver::species_diffusion() {
  const auto state = coefficient_state();
  std::vector<rd::SpeciesCoefficients> coefficients;
  model_.coefficients(0.0, state, rd::VertexData{local_ids_, local_xyz_}, coefficients);
  std::vector<double> diffusion;
  for (const auto& c : coefficients)
    diffusion.push_back(c.diffusion);
  return diffusion;
}

std::vector<double> ReactionDiffusionSolver::system_values(std::span<const double> weight,
                                                           std::size_t s,
                                                           bool geometry_only) const {
  std::vector<double> values = assembler_->mass_values(weight, options_.lumped_mass);
  const bool tensor =
      field_ && field_->applies_to(names_[s]) && !(geometry_only && field_->depends_on_species());
  const std::vector<double>& stiffness = tensor ? field_stiffness_ : stiffness_;
  for (std::size_t k = 0; k < values.size(); ++k)
    values[k] += options_.dt * diffusion_[s] * stiffness[k];
  return values;
}

par::Preconditioner ReactionDiffusionSolver::choose_preconditioner() {
  switch (options_.preconditioner) {
  case RdPreconditioner::kJacobi:
    return par::Preconditioner::kJacobi;
  case RdPreconditioner::kGamg:
    return par::Preconditioner::kGamg;
  case RdPreconditioner::kBoomerAmg:
    return par::Preconditioner::kBoomerAmg;
  case RdPreconditioner::kAuto:
    break;
  }
  // Probe: solve P x = M r from zero for the fastest-diffusing species (its system is the least
  // diagonally dominant), r uniform in [-1, 1] keyed by input vertex id. It depends only on the
  // geometry, so a restarted run makes the same choice.
  const auto fastest =
      std::size_t(std::max_element(diffusion_.begin(), diffusion_.end()) - diffusion_.begin());
  par::PetscMat probe = assembler_->create_matrix(comm_);
  assembler_->set_values(probe, system_values({}, fastest, true));
  par::PetscVec x;
  TEXSIM_PETSC_CALL(VecDuplicate(rhs_, x.address()));
  const CounterRng rng(0, kProbeStream);
  double* values = nullptr;
  TEXSIM_PETSC_CALL(VecGetArray(explicit_part_, &values));
  for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
    values[v] = rng.uniform(-1.0, 1.0, std::uint64_t(local_ids_[v]), 0);
  TEXSIM_PETSC_CALL(VecRestoreArray(explicit_part_, &values));
  TEXSIM_PETSC_CALL(MatMult(mass_, explicit_part_, rhs_));
  TEXSIM_PETSC_CALL(VecSet(x, 0.0));
  par::CgSolver jacobi(comm_, options_.rtol, par::Preconditioner::kJacobi);
  probe_converged_ = jacobi.solve_within(probe, rhs_, x, kJacobiProbeLimit);
  probe_iterations_ = int(jacobi.stats().iterations);
  if (probe_converged_) {
    log::info(log::cat("fem_rd: CG + Jacobi probe solve converged in ", probe_iterations_,
                       " iterations (limit ", kJacobiProbeLimit, "): Jacobi preconditioner"));
    return par::Preconditioner::kJacobi;
  }
  log::info(log::cat("fem_rd: CG + Jacobi probe solve did not converge in ", kJacobiProbeLimit,
                     " iterations (badly shaped triangles; fem_rd.mesh.remesh would help): "
                     "BoomerAMG preconditioner, set up once from M + dt D K"));
  return par::Preconditioner::kBoomerAmg;
}

void ReactionDiffusionSolver::assemble_preconditioners() {
  for (std::size_t s = 0; s < preconditioning_.size(); ++s)
    assembler_->set_values(preconditioning_[s], system_values({}, s, true));
}

void ReactionDiffusionSolver::record_step_iterations(long long iterations) {
  step_iterations_.push_back(iterations);
  const double per_solve = double(iterations) / double(fields_.size());
  if (warned_ || per_solve <= kWarnIterations)
    return;
  warned_ = true;
  log::warn(log::cat("fem_rd: CG needed ", per_solve, " iterations per solve on this step with ",
                     par::preconditioner_name(preconditioner_), " (more than ", kWarnIterations,
                     "): the mesh has badly shaped triangles (slivers, needles); remesh it with "
                     "fem_rd.mesh.remesh: {edge_length: L}, L about the mean edge length ",
                     mean_edge_length_, " or larger"));
}

nlohmann::json ReactionDiffusionSolver::solver_metrics() const {
  const long long total = std::accumulate(step_iterations_.begin(), step_iterations_.end(), 0LL);
  nlohmann::json metrics = {
      {"preconditioner", par::preconditioner_name(preconditioner_)},
      {"choice", options_.preconditioner == RdPreconditioner::kAuto ? "auto" : "config"},
      {"iterations_per_step", step_iterations_},
      {"iterations_per_step_mean",
       step_iterations_.empty() ? 0.0 : double(total) / double(step_iterations_.size())},
      {"iterations_per_step_max",
       step_iterations_.empty()
           ? 0LL
           : *std::max_element(step_iterations_.begin(), step_iterations_.end())}};
  if (probe_iterations_ >= 0)
    metrics["jacobi_probe"] = {{"iterations", probe_iterations_},
                               {"converged", probe_converged_},
                               {"limit", kJacobiProbeLimit}};
  return metrics;
}

void ReactionDiffusionSolver::refresh_vertex_data() {
  const std::int32_t n = assembler_->coefficient_count();
  local_ids_.resize(n);
  local_xyz_.resize(3 * std::size_t(n));
  for (std::int32_t local = 0; local < n; ++local) {
    local_ids_[local] = mesh_.input_id()[local];
    for (int axis = 0; axis < 3; ++axis)
      local_xyz_[3 * local + axis] = mesh_.mesh().positions[local][axis];
  }
}

void ReactionDiffusionSolver::rebuild_geometry() {
  refresh_vertex_data();
  assembler_->update_geometry();
  assembler_->set_values(mass_, assembler_->mass_values({}, options_.lumped_mass));
  stiffness_ = assembler_->stiffness_values({});
  if (field_ && !field_->depends_on_species())
    assemble_field_stiffness();
  mean_edge_length_ = geom::mean_edge_length(mesh_);
  if (!preconditioning_.empty())
    assemble_preconditioners();
}

void ReactionDiffusionSolver::assemble_field_stiffness() {
  const auto state = coefficient_state();
  const auto count = std::size_t(assembler_->coefficient_count());
  field_->update_mesh_fields(mesh_.mesh());
  std::vector<double> tensors; // a bad scale on some ranks' vertices fails every rank
  par::run_collectively(comm_, [&] { tensors = field_->tensors(mesh_.mesh(), count, state); });
  // Tangent planes at the halo's rim come from cut-off fans; Loop's controls reach that far, so
  // every non-owned tensor is taken from its owner.
  if (count > std::size_t(mesh_.local_count()))
    mesh_.update_halo(tensors, 9);
  field_stiffness_ = assembler_->stiffness_values(tensors);
}

void ReactionDiffusionSolver::step(double t) {
  if (field_ && field_->depends_on_species()) // the rates of u^n, as C2 and C3 are
    assemble_field_stiffness();
  const auto state = coefficient_state();
  const rd::VertexData vertices{local_ids_, local_xyz_};
  model_.coefficients(t, state, vertices, coefficients_);
  TEXSIM_VERIFY(coefficients_.size() == fields_.size(), "model gave coefficients for "
                                                            << coefficients_.size() << " of "
                                                            << fields_.size() << " species");

  const double dt = options_.dt;
  std::vector<double> weight(std::size_t(assembler_->coefficient_count()));
  long long iterations = 0;
  for (std::size_t s = 0; s < fields_.size(); ++s) {
    const auto& c = coefficients_[s];
    for (std::size_t v = 0; v < weight.size(); ++v)
      weight[v] = 1.0 - dt * std::min(c.linear[v], 0.0);
    assembler_->set_values(systems_[s], system_values(weight, s, false));

    // Right-hand side M (u^n + tau C3): the P1 interpolant of C3 integrates exactly.
    double* explicit_values = nullptr;
    TEXSIM_PETSC_CALL(VecGetArray(explicit_part_, &explicit_values));
    const auto u = fields_[s]->local();
    for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
      explicit_values[v] = u[v] + dt * (c.source[v] + std::max(c.linear[v], 0.0) * u[v]);
    TEXSIM_PETSC_CALL(VecRestoreArray(explicit_part_, &explicit_values));
    TEXSIM_PETSC_CALL(MatMult(mass_, explicit_part_, rhs_));
    const long long before = solvers_[s]->stats().iterations;
    if (preconditioning_.empty())
      solvers_[s]->solve(systems_[s], rhs_, fields_[s]->vec());
    else
      solvers_[s]->solve(systems_[s], preconditioning_[s], rhs_, fields_[s]->vec());
    iterations += solvers_[s]->stats().iterations - before;
    clamp_to_lower_bound(s);
  }
  for (auto& field : fields_)
    field->update_ghosts();
  record_step_iterations(iterations);
}

void ReactionDiffusionSolver::clamp_to_lower_bound(std::size_t s) {
  const double bound = model_.lower_bound(s);
  if (!std::isfinite(bound))
    return;
  double* values = nullptr;
  TEXSIM_PETSC_CALL(VecGetArray(fields_[s]->vec(), &values));
  for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
    values[v] = std::max(values[v], bound);
  TEXSIM_PETSC_CALL(VecRestoreArray(fields_[s]->vec(), &values));
}

void ReactionDiffusionSolver::set_owned_values(std::size_t s, std::span<const double> owned) {
  fields_[s]->set_owned(owned);
}

double ReactionDiffusionSolver::integral(std::size_t s) const {
  TEXSIM_PETSC_CALL(MatMult(mass_, fields_[s]->vec(), rhs_));
  double total = 0;
  TEXSIM_PETSC_CALL(VecDot(rhs_, ones_, &total));
  return total;
}

} // namespace texsim::pipelines::fem_rd
