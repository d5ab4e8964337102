// One step of the fem_rd pipeline (Turing spots model, both species) on a level-L icosphere and
// what it is made of: system matrix assembly, the CG solves (per solve, per iteration, against a
// bare MatMult), ghost updates; for both vertex partitions (Morton curve, Scotch) and for the
// preconditioners block Jacobi + ICC(0) (texsim's default), the same with the ICC factor in
// reverse Cuthill-McKee order, Jacobi and GAMG. Plus the backward Euler heat step
// (M + tau K) u = M u^n on the unit sphere that bench/dolfinx_heat_step.py times in DOLFINx.
// Prints one JSON object on rank 0: medians over --repeats runs, each timed between MPI barriers;
// the runs of the variants are interleaved so that a shared machine's load hits them alike.
// The benchmark sets -pc_type and -sub_pc_factor_mat_ordering_type itself, per variant.
// Sample run:
//   OMP_NUM_THREADS=1 mpirun -n 2 build/release/bench/fem_step_bench --level 7 --repeats 5
#include "bench_timing.hpp"
#include "core/config.hpp"
#include "core/log.hpp"
#include "geom/distributed_mesh.hpp"
#include "geom/generators.hpp"
#include "par/cg_solver.hpp"
#include "par/ghosted_vector.hpp"
#include "par/petsc_session.hpp"
#include "pipelines/fem_rd/p1_assembler.hpp"
#include "pipelines/fem_rd/reaction_diffusion_solver.hpp"
#include "rd/reaction_model.hpp"

#include <mpi.h>
#include <nlohmann/json.hpp>
#include <omp.h>
#include <petsclog.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {
using texsim::geom::DistributedMesh;
using texsim::geom::PartitionMethod;
using texsim::par::Comm;
using namespace texsim::pipelines::fem_rd;
namespace rd = texsim::rd;

struct BenchSettings {
  int level = 7;
  double radius = 100.0; ///< of the reaction-diffusion sphere (the level-4 spot test uses 12)
  int repeats = 5;
  int warmup = 3;         ///< reaction-diffusion steps before timing
  double dt = 0.5;        ///< RdOptions default
  double rd_rtol = 1e-10; ///< RdOptions default
  double tau = 1e-3;      ///< heat step, as bench/dolfinx_heat_step.py
  double heat_rtol = 1e-8;
};

// The Turing spots model of Fig. 3 (c) of Bajaj, Zhang, Xu (s = 0.05), as the pipeline builds it.
constexpr const char* kTuringYaml = "type: turing_spots\ns: 0.05\n";

using texsim::bench::max_over_ranks;
using texsim::bench::median;
using texsim::bench::peak_memory_mb;
using texsim::bench::timed;

std::vector<double> repeated_times(const Comm& comm, int repeats,
                                   const std::function<void()>& work) {
  std::vector<double> seconds;
  for (int r = 0; r < repeats; ++r)
    seconds.push_back(timed(comm, work));
  return seconds;
}

double median_time(const Comm& comm, int repeats, const std::function<void()>& work) {
  return median(repeated_times(comm, repeats, work));
}

/// Seconds (maximum over ranks) and call count of a PETSc event inside a log stage. Collective.
struct EventTotals {
  double seconds = 0;
  int count = 0;
};

EventTotals event_totals(const Comm& comm, PetscLogStage stage, const char* event_name) {
  PetscLogEvent event = 0;
  TEXSIM_PETSC_CALL(PetscLogEventGetId(event_name, &event));
  PetscEventPerfInfo info{};
  TEXSIM_PETSC_CALL(PetscLogEventGetPerfInfo(stage, event, &info));
  return {max_over_ranks(comm, info.time), info.count};
}

PetscLogStage log_stage(const std::string& name) {
  PetscLogStage stage = 0;
  TEXSIM_PETSC_CALL(PetscLogStageRegister(name.c_str(), &stage));
  return stage;
}

/// Runs `work` with the PETSc options of a preconditioner variant in the options database, then
/// removes them: "default" is texsim's block Jacobi + ICC(0), "icc_rcm" the same with the ICC
/// factor in reverse Cuthill-McKee order, any other name a -pc_type. A KSP reads -pc_type when it
/// is created and the block solvers read theirs at the first solve, so `work` creates the solver
/// and solves at least once. Collective.
template <class Work> void with_pc_variant(const std::string& variant, Work work) {
  std::vector<std::pair<const char*, std::string>> options;
  if (variant == "icc_rcm")
    options = {{"-sub_pc_factor_mat_ordering_type", "rcm"}};
  else if (variant != "default")
    options = {{"-pc_type", variant}};
  for (const auto& [name, value] : options)
    TEXSIM_PETSC_CALL(PetscOptionsSetValue(nullptr, name, value.c_str()));
  work();
  for (const auto& [name, value] : options)
    TEXSIM_PETSC_CALL(PetscOptionsClearValue(nullptr, name));
}

/// Ids and positions of a rank's local vertices (owned, then ghosts), as the solver builds them.
struct LocalVertices {
  std::vector<std::int64_t> ids;
  std::vector<double> xyz;
  rd::VertexData view() const { return {ids, xyz}; }
};

LocalVertices local_vertices(const DistributedMesh& mesh) {
  LocalVertices local;
  // The rank's mesh is its part, numbered locally (owned vertices first).
  for (std::int32_t v = 0; v < mesh.local_count(); ++v) {
    local.ids.push_back(mesh.input_id()[std::size_t(v)]);
    for (int axis = 0; axis < 3; ++axis)
      local.xyz.push_back(mesh.mesh().positions[std::size_t(v)][axis]);
  }
  return local;
}

nlohmann::json quality_json(const DistributedMesh& mesh, double partition_s) {
  const auto& q = mesh.quality();
  return {{"edge_cut", q.edge_cut},
          {"imbalance", q.imbalance},
          {"ghosts_max", q.ghosts_max},
          {"partition_s", partition_s}};
}

/// Solve timings of one CgSolver on A x = b: median seconds with the preconditioner rebuilt
/// (A's values set again just before, untimed) and reused, and the mean iteration count. Every
/// solve starts from `guess`. Collective.
struct SolveTimes {
  double with_setup_s = 0;
  double reused_s = 0;
  double iterations = 0;
};

SolveTimes time_solves(const Comm& comm, int repeats, texsim::par::CgSolver& solver,
                       const P1Assembler& assembler, Mat system, const std::vector<double>& values,
                       Vec rhs, Vec guess, Vec x) {
  const texsim::par::SolveStats before = solver.stats();
  std::vector<double> with_setup, reused;
  for (int r = 0; r < repeats; ++r) {
    assembler.set_values(system, values);
    TEXSIM_PETSC_CALL(VecCopy(guess, x));
    with_setup.push_back(timed(comm, [&] { solver.solve(system, rhs, x); }));
    TEXSIM_PETSC_CALL(VecCopy(guess, x));
    reused.push_back(timed(comm, [&] { solver.solve(system, rhs, x); }));
  }
  const texsim::par::SolveStats after = solver.stats();
  return {median(with_setup), median(reused),
          double(after.iterations - before.iterations) / double(after.solves - before.solves)};
}

/// The work of species 0 in one step, each piece timed alone from the state `state` (both
/// species, local values): the model's coefficients (all species), the system matrix
/// M_w + dt D K from the per-vertex weight w = 1 - dt min(C2, 0) and the stored stiffness, the
/// same matrix from scratch, the right-hand side MatMult, the CG solve from u^n with the
/// preconditioner rebuilt (as in every step) and reused, one MatMult with the system matrix
/// and one ghost update. The solve is timed with `pipeline_preconditioner` (what the RD solver
/// chose for this mesh) and, under "icc", with block Jacobi + ICC(0). Collective.
nlohmann::json measure_species_step(const Comm& comm, const DistributedMesh& mesh,
                                    const rd::ReactionModel& model,
                                    const std::vector<std::vector<double>>& state,
                                    texsim::par::Preconditioner pipeline_preconditioner,
                                    const BenchSettings& settings) {
  const LocalVertices vertices = local_vertices(mesh);
  const std::vector<std::span<const double>> views(state.begin(), state.end());
  std::vector<rd::SpeciesCoefficients> coefficients;
  const double coefficients_s = median_time(comm, settings.repeats, [&] {
    model.coefficients(0.0, views, vertices.view(), coefficients);
  });
  const rd::SpeciesCoefficients& species = coefficients.front();
  std::vector<double> weight(mesh.local_count());
  for (std::size_t v = 0; v < weight.size(); ++v)
    weight[v] = 1.0 - settings.dt * std::min(species.linear[v], 0.0);

  const P1Assembler assembler(mesh);
  texsim::par::PetscMat system = assembler.create_matrix(comm);
  texsim::par::PetscMat mass = assembler.create_matrix(comm);
  assembler.set_values(mass, assembler.mass_values({}, false));
  const std::vector<double> stiffness = assembler.stiffness_values({});
  const auto add_stiffness = [&](std::vector<double>& values, const std::vector<double>& k) {
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] += settings.dt * species.diffusion * k[i];
  };
  std::vector<double> values;
  const double mass_values_s =
      median_time(comm, settings.repeats, [&] { values = assembler.mass_values(weight, false); });
  const double stiffness_values_s =
      median_time(comm, settings.repeats, [&] { (void)assembler.stiffness_values({}); });
  add_stiffness(values, stiffness);
  const double set_values_s =
      median_time(comm, settings.repeats, [&] { assembler.set_values(system, values); });
  const double assembly_s = median_time(comm, settings.repeats, [&] {
    std::vector<double> v = assembler.mass_values(weight, false);
    add_stiffness(v, stiffness);
    assembler.set_values(system, v);
  });
  const double assembly_full_s = median_time(comm, settings.repeats, [&] {
    std::vector<double> v = assembler.mass_values({}, false);
    add_stiffness(v, assembler.stiffness_values({}));
    assembler.set_values(system, v);
  });

  // Right-hand side M (u^n + dt (C3 + max(C2, 0) u^n)) and the initial guess u^n, as step().
  texsim::par::PetscVec u, explicit_part, rhs, x;
  TEXSIM_PETSC_CALL(MatCreateVecs(system, u.address(), rhs.address()));
  TEXSIM_PETSC_CALL(VecDuplicate(u, explicit_part.address()));
  TEXSIM_PETSC_CALL(VecDuplicate(u, x.address()));
  double* u_values = nullptr;
  double* explicit_values = nullptr;
  TEXSIM_PETSC_CALL(VecGetArray(u, &u_values));
  TEXSIM_PETSC_CALL(VecGetArray(explicit_part, &explicit_values));
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v) {
    const double un = state.front()[v];
    u_values[v] = un;
    explicit_values[v] =
        un + settings.dt * (species.source[v] + std::max(species.linear[v], 0.0) * un);
  }
  TEXSIM_PETSC_CALL(VecRestoreArray(explicit_part, &explicit_values));
  TEXSIM_PETSC_CALL(VecRestoreArray(u, &u_values));
  const double rhs_matmult_s = median_time(
      comm, 4 * settings.repeats, [&] { TEXSIM_PETSC_CALL(MatMult(mass, explicit_part, rhs)); });
  const double matmult_s =
      median_time(comm, 4 * settings.repeats, [&] { TEXSIM_PETSC_CALL(MatMult(system, u, x)); });
  // The solve with the preconditioner the pipeline's solver chose, and with block Jacobi + ICC(0)
  // (the stiffness-dominated default) for comparison.
  const auto solve_json = [&](texsim::par::Preconditioner preconditioner) {
    texsim::par::CgSolver solver(comm, settings.rd_rtol, preconditioner);
    const SolveTimes solve =
        time_solves(comm, settings.repeats, solver, assembler, system, values, rhs, u, x);
    return nlohmann::json{
        {"preconditioner", texsim::par::preconditioner_name(preconditioner)},
        {"cg_solve_s", solve.with_setup_s},
        {"cg_solve_reused_pc_s", solve.reused_s},
        {"pc_setup_s", solve.with_setup_s - solve.reused_s},
        {"cg_iters", solve.iterations},
        {"cg_iteration_s", solve.reused_s / solve.iterations},
        {"cg_iteration_over_matmult", solve.reused_s / solve.iterations / matmult_s}};
  };
  nlohmann::json result = solve_json(pipeline_preconditioner);
  result["icc"] = solve_json(texsim::par::Preconditioner::kBlockJacobiIcc);
  texsim::par::GhostedVector field(comm, mesh.owned_count(), mesh.ghosts());
  const double ghost_update_s =
      median_time(comm, 4 * settings.repeats, [&] { field.update_ghosts(); });
  MatInfo info{};
  TEXSIM_PETSC_CALL(MatGetInfo(system, MAT_GLOBAL_SUM, &info));
  result.update({{"coefficients_s", coefficients_s},
                 {"mass_values_s", mass_values_s},
                 {"stiffness_values_s", stiffness_values_s},
                 {"set_values_s", set_values_s},
                 {"assembly_s", assembly_s},
                 {"assembly_full_s", assembly_full_s},
                 {"rhs_matmult_s", rhs_matmult_s},
                 {"matmult_s", matmult_s},
                 {"ghost_update_s", ghost_update_s},
                 {"matrix_nnz", static_cast<long long>(info.nz_used)}});
  return result;
}

/// One configuration of the reaction-diffusion step: a partition and a preconditioner
/// (`pc_variant` as in with_pc_variant), timed over `repeats` steps.
struct RdVariant {
  std::string label;
  const DistributedMesh* mesh = nullptr;
  std::string pc_variant;
  int repeats = 0;
};

/// ReactionDiffusionSolver::step of the Turing model for each variant after --warmup steps (at
/// least one). The
/// timed steps of the variants are interleaved (one step of each in turn), so that a change of
/// load on a shared machine affects them alike. The CG solves' share of a step comes from PETSc's
/// event log (KSPSolve, which includes the preconditioner set-up: the matrix changes every
/// step). `first_state` receives the local values of every species of the first variant at the
/// end, `first_preconditioner` the preconditioner its solver chose. Collective.
std::vector<nlohmann::json> measure_rd_steps(const Comm& comm, const rd::ReactionModel& model,
                                             const BenchSettings& settings,
                                             const std::vector<RdVariant>& variants,
                                             std::vector<std::vector<double>>& first_state,
                                             texsim::par::Preconditioner& first_preconditioner) {
  struct Run {
    std::unique_ptr<ReactionDiffusionSolver> solver;
    PetscLogStage stage = 0;
    double t = 0;
    std::vector<double> seconds;
    long long solves = 0, iterations = 0;
  };
  const auto add_stats = [](const ReactionDiffusionSolver& solver, long long sign, Run& run) {
    for (std::size_t s = 0; s < solver.species_count(); ++s) {
      run.solves += sign * solver.solve_stats(s).solves;
      run.iterations += sign * solver.solve_stats(s).iterations;
    }
  };
  std::vector<Run> runs(variants.size());
  int most_repeats = 0;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const RdVariant& variant = variants[i];
    Run& run = runs[i];
    with_pc_variant(variant.pc_variant, [&] {
      run.solver = std::make_unique<ReactionDiffusionSolver>(
          comm, *variant.mesh, model, RdOptions{settings.dt, false, settings.rd_rtol});
      for (int n = 0; n < std::max(settings.warmup, 1); ++n, run.t += settings.dt)
        run.solver->step(run.t);
    });
    add_stats(*run.solver, -1, run);
    run.stage = log_stage("rd_step_" + variant.label);
    most_repeats = std::max(most_repeats, variant.repeats);
  }
  for (int r = 0; r < most_repeats; ++r) {
    for (std::size_t i = 0; i < variants.size(); ++i) {
      if (r >= variants[i].repeats)
        continue;
      Run& run = runs[i];
      TEXSIM_PETSC_CALL(PetscLogStagePush(run.stage));
      run.seconds.push_back(timed(comm, [&] { run.solver->step(run.t); }));
      TEXSIM_PETSC_CALL(PetscLogStagePop());
      run.t += settings.dt;
    }
  }

  std::vector<nlohmann::json> results;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    Run& run = runs[i];
    add_stats(*run.solver, 1, run);
    const EventTotals ksp = event_totals(comm, run.stage, "KSPSolve");
    bool finite = true;
    for (std::size_t s = 0; s < run.solver->species_count(); ++s)
      for (const double value : run.solver->local_values(s))
        finite = finite && std::isfinite(value);
    int all_finite = 0, local_finite = finite;
    MPI_Allreduce(&local_finite, &all_finite, 1, MPI_INT, MPI_MIN, comm.raw);
    double total = 0;
    for (const double s : run.seconds)
      total += s;
    results.push_back({{"solver", run.solver->solver_description()},
                       {"rd_step_s", median(run.seconds)},
                       {"rd_step_min_s", *std::min_element(run.seconds.begin(), run.seconds.end())},
                       {"cg_iters_mean", double(run.iterations) / double(run.solves)},
                       {"cg_solve_s", ksp.seconds / ksp.count},
                       {"ksp_share_of_step", ksp.seconds / total},
                       {"steps_timed", variants[i].repeats},
                       {"state_finite", all_finite == 1}});
  }
  first_preconditioner = runs.front().solver->preconditioner();
  first_state.clear();
  for (std::size_t s = 0; s < runs.front().solver->species_count(); ++s) {
    const auto local = runs.front().solver->local_values(s);
    first_state.emplace_back(local.begin(), local.end());
  }
  return results;
}

/// The backward Euler heat step (M + tau K) u = M u^n on the unit sphere from u^0 = 3z^2 - 1 + 1
/// with one preconditioner variant (as in with_pc_variant), set up as bench/dolfinx_heat_step.py:
/// step() is the right-hand side + CG solve from a zero initial guess with the matrix and the
/// preconditioner reused.
class HeatStep {
public:
  /// Assembles, creates the solver and takes the first step (timed). Collective.
  HeatStep(const Comm& comm, const DistributedMesh& mesh, const BenchSettings& settings,
           const std::string& pc_variant)
      : comm_(comm), settings_(settings), assembler_(mesh) {
    mass_ = assembler_.create_matrix(comm);
    system_ = assembler_.create_matrix(comm);
    assembler_.set_values(mass_, assembler_.mass_values({}, false));
    assemble_system();
    TEXSIM_PETSC_CALL(MatCreateVecs(mass_, u_.address(), rhs_.address()));
    for (auto* vec : {&harmonic_, &x_, &zero_, &ones_, &work_})
      TEXSIM_PETSC_CALL(VecDuplicate(u_, vec->address()));
    double* values = nullptr;
    TEXSIM_PETSC_CALL(VecGetArray(harmonic_, &values));
    for (std::int32_t v = 0; v < mesh.owned_count(); ++v) {
      const double z = mesh.mesh().positions[std::size_t(v)].z(); // owned vertices come first
      values[v] = 3.0 * z * z - 1.0;
    }
    TEXSIM_PETSC_CALL(VecRestoreArray(harmonic_, &values));
    TEXSIM_PETSC_CALL(VecSet(ones_, 1.0));
    TEXSIM_PETSC_CALL(VecWAXPY(u_, 1.0, ones_, harmonic_));
    with_pc_variant(pc_variant, [&] {
      solver_ = std::make_unique<texsim::par::CgSolver>(comm, settings.heat_rtol);
      first_step_s_ = timed(comm, [&] { step(); });
    });
  }

  /// Right-hand side M u^n and the solve. Collective.
  void step() {
    TEXSIM_PETSC_CALL(VecZeroEntries(x_));
    TEXSIM_PETSC_CALL(MatMult(mass_, u_, rhs_));
    solver_->solve(system_, rhs_, x_);
  }

  /// The other timings: the solve alone with the preconditioner rebuilt and reused, a step with
  /// matrix assembly from scratch, one MatMult, and the decay of the l = 2 mode after a step
  /// (about 1 / (1 + 6 tau)). Collective.
  nlohmann::json details() {
    step();
    const double decay_factor = projection(x_) / projection(u_);
    const double step_with_assembly_s = median_time(comm_, settings_.repeats, [&] {
      assemble_system();
      step();
    });
    const SolveTimes solve = time_solves(comm_, settings_.repeats, *solver_, assembler_, system_,
                                         system_values_, rhs_, zero_, x_);
    const double matmult_s = median_time(
        comm_, 4 * settings_.repeats, [&] { TEXSIM_PETSC_CALL(MatMult(system_, ones_, work_)); });
    return {{"solver", solver_->description()},
            {"heat_cg_iters", solve.iterations},
            {"solve_s", solve.reused_s},
            {"pc_setup_s", solve.with_setup_s - solve.reused_s},
            {"cg_iteration_s", solve.reused_s / solve.iterations},
            {"first_step_s", first_step_s_},
            {"step_with_assembly_s", step_with_assembly_s},
            {"matmult_s", matmult_s},
            {"decay_factor", decay_factor},
            {"decay_expected", 1.0 / (1.0 + 6.0 * settings_.tau)}};
  }

private:
  void assemble_system() {
    system_values_ = assembler_.mass_values({}, false);
    const std::vector<double> stiffness = assembler_.stiffness_values({});
    for (std::size_t i = 0; i < system_values_.size(); ++i)
      system_values_[i] += settings_.tau * stiffness[i];
    assembler_.set_values(system_, system_values_);
  }

  // (v - mean, Y)_L2 = Y^T M v - (1^T M v / 1^T M 1) Y^T M 1.
  double projection(Vec v) {
    double mass_y = 0, mass_v = 0, area = 0, y_integral = 0;
    TEXSIM_PETSC_CALL(MatMult(mass_, v, work_));
    TEXSIM_PETSC_CALL(VecDot(harmonic_, work_, &mass_y));
    TEXSIM_PETSC_CALL(VecDot(ones_, work_, &mass_v));
    TEXSIM_PETSC_CALL(MatMult(mass_, ones_, work_));
    TEXSIM_PETSC_CALL(VecDot(ones_, work_, &area));
    TEXSIM_PETSC_CALL(VecDot(harmonic_, work_, &y_integral));
    return mass_y - mass_v / area * y_integral;
  }

  Comm comm_;
  BenchSettings settings_;
  P1Assembler assembler_;
  texsim::par::PetscMat mass_, system_;
  std::vector<double> system_values_;
  texsim::par::PetscVec u_, rhs_, harmonic_, x_, zero_, ones_, work_;
  std::unique_ptr<texsim::par::CgSolver> solver_;
  double first_step_s_ = 0;
};

/// heat_step_s (median and minimum) of every preconditioner variant, the variants' steps
/// interleaved as in measure_rd_steps, plus each variant's details(). Collective.
std::vector<nlohmann::json> measure_heat_steps(const Comm& comm, const DistributedMesh& mesh,
                                               const BenchSettings& settings,
                                               const std::vector<std::string>& variants) {
  std::vector<std::unique_ptr<HeatStep>> heat;
  for (const std::string& variant : variants)
    heat.push_back(std::make_unique<HeatStep>(comm, mesh, settings, variant));
  std::vector<std::vector<double>> seconds(variants.size());
  for (int r = 0; r < 2 * settings.repeats; ++r)
    for (std::size_t i = 0; i < variants.size(); ++i)
      seconds[i].push_back(timed(comm, [&] { heat[i]->step(); }));
  std::vector<nlohmann::json> results;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    nlohmann::json result = heat[i]->details();
    result["heat_step_s"] = median(seconds[i]);
    result["heat_step_min_s"] = *std::min_element(seconds[i].begin(), seconds[i].end());
    results.push_back(result);
  }
  return results;
}

BenchSettings parse_arguments(int argc, char** argv) {
  BenchSettings settings;
  for (int i = 1; i + 1 < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--level")
      settings.level = std::stoi(argv[++i]);
    else if (flag == "--radius")
      settings.radius = std::stod(argv[++i]);
    else if (flag == "--repeats")
      settings.repeats = std::stoi(argv[++i]);
    else if (flag == "--warmup")
      settings.warmup = std::stoi(argv[++i]);
  }
  return settings;
}

} // namespace

int main(int argc, char** argv) {
  texsim::par::PetscSession session(argc, argv);
  const Comm comm = texsim::par::world();
  texsim::log::init(comm.rank, /*quiet=*/true); // stdout holds the JSON only
  const BenchSettings settings = parse_arguments(argc, argv);
  TEXSIM_PETSC_CALL(PetscLogDefaultBegin());

  const texsim::geom::TriangleMesh sphere =
      texsim::geom::icosphere(settings.level, settings.radius);
  std::unique_ptr<DistributedMesh> morton, scotch;
  const double morton_s = timed(comm, [&] {
    morton = std::make_unique<DistributedMesh>(comm, sphere, PartitionMethod::kMorton);
  });
  const double scotch_s = timed(comm, [&] {
    scotch = std::make_unique<DistributedMesh>(comm, sphere, PartitionMethod::kScotch);
  });
  const double meshes_memory_mb = peak_memory_mb(comm);
  auto config = texsim::ConfigDocument::parse(kTuringYaml, "fem_step_bench");
  const auto model = rd::make_reaction_model(config.root(), 1);

  // Scotch is the pipeline's default partition: the headline figures use it. The pieces of a
  // step are timed from the state the default run reached.
  std::vector<std::vector<double>> state;
  texsim::par::Preconditioner rd_preconditioner{};
  const std::vector<nlohmann::json> rd_runs =
      measure_rd_steps(comm, *model, settings,
                       {{"scotch", scotch.get(), "default", settings.repeats},
                        {"morton", morton.get(), "default", settings.repeats},
                        {"jacobi", scotch.get(), "jacobi", settings.repeats},
                        {"icc_rcm", scotch.get(), "icc_rcm", settings.repeats},
                        {"gamg", scotch.get(), "gamg", 3}},
                       state, rd_preconditioner);
  const nlohmann::json& rd = rd_runs[0];
  const nlohmann::json& rd_morton = rd_runs[1];
  const nlohmann::json& rd_jacobi = rd_runs[2];
  const nlohmann::json& rd_icc_rcm = rd_runs[3];
  const nlohmann::json& rd_gamg = rd_runs[4];
  const nlohmann::json pieces =
      measure_species_step(comm, *scotch, *model, state, rd_preconditioner, settings);

  const DistributedMesh unit_sphere(comm, texsim::geom::icosphere(settings.level, 1.0),
                                    PartitionMethod::kScotch);
  const std::vector<nlohmann::json> heat_runs =
      measure_heat_steps(comm, unit_sphere, settings, {"default", "icc_rcm", "gamg"});
  const nlohmann::json& heat = heat_runs[0];
  const nlohmann::json& heat_icc_rcm = heat_runs[1];
  const nlohmann::json& heat_gamg = heat_runs[2];
  const double memory_mb = peak_memory_mb(comm);

  if (comm.is_root()) {
    nlohmann::json partition = {{"morton", quality_json(*morton, morton_s)},
                                {"scotch", quality_json(*scotch, scotch_s)}};
    for (const auto& [name, run] : {std::pair{"morton", &rd_morton}, {"scotch", &rd}}) {
      partition[name]["rd_step_s"] = (*run)["rd_step_s"];
      partition[name]["cg_iters_mean"] = (*run)["cg_iters_mean"];
    }
    const double rd_step_s = rd["rd_step_s"];
    const double coefficients_s = pieces["coefficients_s"];
    const double assembly_s = pieces["assembly_s"];
    const double rhs_matmult_s = pieces["rhs_matmult_s"];
    const double cg_solve_s = pieces["cg_solve_s"];
    const double ghost_update_s = pieces["ghost_update_s"];
    // A step: coefficients once; per species assembly, rhs MatMult, solve and a ghost update.
    const nlohmann::json breakdown = {
        {"coefficients_s", coefficients_s},
        {"assembly_s", 2 * assembly_s},
        {"rhs_matmult_s", 2 * rhs_matmult_s},
        {"cg_solve_s", 2 * cg_solve_s},
        {"ghost_update_s", 2 * ghost_update_s},
        {"rest_s", rd_step_s - coefficients_s -
                       2 * (assembly_s + rhs_matmult_s + cg_solve_s + ghost_update_s)}};
    const nlohmann::json result = {
        {"benchmark", "fem_step"},
        {"ranks", comm.size},
        {"threads", omp_get_max_threads()},
        {"level", settings.level},
        {"vertices", sphere.num_vertices()},
        {"triangles", sphere.triangles.size()},
        {"rd_radius", settings.radius},
        {"heat_radius", 1.0},
        {"dt", settings.dt},
        {"rd_rtol", settings.rd_rtol},
        {"tau", settings.tau},
        {"heat_rtol", settings.heat_rtol},
        {"repeats", settings.repeats},
        {"warmup_steps", settings.warmup},
        {"default_partition", "scotch"},
        {"assembly_s", assembly_s},
        {"assembly_full_s", pieces["assembly_full_s"]},
        {"rd_step_s", rd_step_s},
        {"rd_step_min_s", rd["rd_step_min_s"]},
        {"cg_iters_mean", rd["cg_iters_mean"]},
        {"cg_solve_s", cg_solve_s},
        {"pc_setup_s", pieces["pc_setup_s"]},
        {"cg_iteration_s", pieces["cg_iteration_s"]},
        {"matmult_s", pieces["matmult_s"]},
        {"cg_preconditioner", pieces["preconditioner"]},
        {"cg_iteration_over_matmult", pieces["cg_iteration_over_matmult"]},
        {"cg_iteration_over_matmult_icc", pieces["icc"]["cg_iteration_over_matmult"]},
        {"heat_cg_iteration_over_matmult",
         double(heat["cg_iteration_s"]) / double(heat["matmult_s"])},
        {"heat_step_s", heat["heat_step_s"]},
        {"heat_step_min_s", heat["heat_step_min_s"]},
        {"heat_cg_iters", heat["heat_cg_iters"]},
        {"heat_step_s_gamg", heat_gamg["heat_step_s"]},
        {"heat_cg_iters_gamg", heat_gamg["heat_cg_iters"]},
        {"heat_step_s_icc_rcm", heat_icc_rcm["heat_step_s"]},
        {"heat_cg_iters_icc_rcm", heat_icc_rcm["heat_cg_iters"]},
        {"rd_step_s_jacobi", rd_jacobi["rd_step_s"]},
        {"rd_step_s_icc_rcm", rd_icc_rcm["rd_step_s"]},
        {"rd_step_s_gamg", rd_gamg["rd_step_s"]},
        {"vm_hwm_mb_max", memory_mb},
        {"vm_hwm_mb_after_meshes", meshes_memory_mb},
        {"partition", partition},
        {"rd_step_breakdown", breakdown},
        {"details",
         {{"rd_step_pieces", pieces},
          {"rd_scotch", rd},
          {"rd_morton", rd_morton},
          {"rd_scotch_jacobi", rd_jacobi},
          {"rd_scotch_icc_rcm", rd_icc_rcm},
          {"rd_scotch_gamg", rd_gamg},
          {"heat_bjacobi_icc", heat},
          {"heat_bjacobi_icc_rcm", heat_icc_rcm},
          {"heat_gamg", heat_gamg}}}};
    std::cout << result.dump() << std::endl;
  }
  return 0;
}
