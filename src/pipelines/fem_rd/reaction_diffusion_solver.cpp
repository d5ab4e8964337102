#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"

#include "core/error.hpp"
#include "par/petsc_session.hpp"

#include <algorithm>
#include <cmath>

namespace texsim::pipelines::fem_rd {

ReactionDiffusionSolver::ReactionDiffusionSolver(const par::Comm& comm,
                                                 const geom::DistributedMesh& mesh,
                                                 const ReactionModel& model,
                                                 const RdOptions& options)
    : comm_(comm), mesh_(mesh), model_(model), options_(options), assembler_(mesh),
      names_(model.species()) {
  mass_ = assembler_.create_matrix(comm);
  for (std::size_t s = 0; s < names_.size(); ++s) {
    fields_.push_back(
        std::make_unique<par::GhostedVector>(comm, mesh.owned_count(), mesh.ghosts()));
    solvers_.push_back(
        std::make_unique<par::CgSolver>(comm, options.rtol, par::Preconditioner::kJacobi));
    systems_.push_back(assembler_.create_matrix(comm));
  }
  TEXSIM_PETSC_CALL(MatCreateVecs(mass_, ones_.address(), rhs_.address()));
  TEXSIM_PETSC_CALL(VecDuplicate(rhs_, explicit_part_.address()));
  TEXSIM_PETSC_CALL(VecSet(ones_, 1.0));
  rebuild_geometry();

  const auto initial = model.initial_state(VertexData{local_ids_, local_xyz_});
  TEXSIM_VERIFY(initial.size() == names_.size(), "model gave " << initial.size()
                                                               << " initial fields for "
                                                               << names_.size() << " species");
  for (std::size_t s = 0; s < names_.size(); ++s)
    fields_[s]->set_owned(std::span(initial[s]).first(mesh.owned_count()));
}

void ReactionDiffusionSolver::refresh_vertex_data() {
  const std::int32_t n = mesh_.local_count();
  local_ids_.resize(n);
  local_xyz_.resize(3 * std::size_t(n));
  for (std::int32_t local = 0; local < n; ++local) {
    const std::int32_t global = mesh_.global_index(local);
    local_ids_[local] = mesh_.input_id()[global];
    for (int axis = 0; axis < 3; ++axis)
      local_xyz_[3 * local + axis] = mesh_.mesh().positions[global][axis];
  }
}

void ReactionDiffusionSolver::rebuild_geometry() {
  refresh_vertex_data();
  assembler_.update_geometry();
  assembler_.set_values(mass_, assembler_.mass_values({}, options_.lumped_mass));
  stiffness_ = assembler_.stiffness_values({});
}

void ReactionDiffusionSolver::step(double t) {
  std::vector<std::span<const double>> state;
  for (const auto& field : fields_)
    state.push_back(field->local());
  const VertexData vertices{local_ids_, local_xyz_};
  model_.coefficients(t, state, vertices, coefficients_);
  TEXSIM_VERIFY(coefficients_.size() == fields_.size(), "model gave coefficients for "
                                                            << coefficients_.size() << " of "
                                                            << fields_.size() << " species");

  const double dt = options_.dt;
  std::vector<double> weight(mesh_.local_count());
  for (std::size_t s = 0; s < fields_.size(); ++s) {
    const auto& c = coefficients_[s];
    for (std::size_t v = 0; v < weight.size(); ++v)
      weight[v] = 1.0 - dt * std::min(c.linear[v], 0.0);
    std::vector<double> values = assembler_.mass_values(weight, options_.lumped_mass);
    for (std::size_t k = 0; k < values.size(); ++k)
      values[k] += dt * c.diffusion * stiffness_[k];
    assembler_.set_values(systems_[s], values);

    // Right-hand side M (u^n + tau C3): the P1 interpolant of C3 integrates exactly.
    double* explicit_values = nullptr;
    TEXSIM_PETSC_CALL(VecGetArray(explicit_part_, &explicit_values));
    const auto u = fields_[s]->local();
    for (std::int32_t v = 0; v < mesh_.owned_count(); ++v)
      explicit_values[v] = u[v] + dt * (c.source[v] + std::max(c.linear[v], 0.0) * u[v]);
    TEXSIM_PETSC_CALL(VecRestoreArray(explicit_part_, &explicit_values));
    TEXSIM_PETSC_CALL(MatMult(mass_, explicit_part_, rhs_));
    solvers_[s]->solve(systems_[s], rhs_, fields_[s]->vec());
    clamp_to_lower_bound(s);
  }
  for (auto& field : fields_)
    field->update_ghosts();
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
