// The turk_rd pipeline's pieces on a real surface (Turk 1991, Part Two): Turk's point relaxation
// of --cells points (geom::relaxed_surface_points, default settings), the whole tiling
// (geom::SurfaceCells: relaxation + restricted Voronoi cells) and the explicit reaction-diffusion
// step of CellRdSolver with the Turing spot model (s = 0.05, diffusion scale 1, dt 1) on those
// cells, against the memory-bandwidth bound of that update: a STREAM triad measured here on every
// rank and thread at once, divided by the bytes one cell update must move at least (own species
// read and written, the stencil row; neighbour values assumed cached). Also what a step is made
// of: the model's coefficients (substrate precomputed, as the solver passes it, and drawn by
// Philox on every call), the counter-based draw alone, the ghost update, and a bench-side fused
// kernel with the solver's data layout and the substrate read from an array, with the cells
// stored by id (as the solver) and along a Morton curve; both must give the solver's values bit
// for bit. The solver's and the fused kernels' runs interleave.
// The mesh is --mesh (default data/meshes/bunny00.off, relative to the working directory); when it
// is missing the run uses icosphere(6) and says so ("mesh_fallback").
// Prints one JSON object on rank 0: medians over repeats, each timed between MPI barriers.
// Sample run:
//   OMP_NUM_THREADS=1 mpirun -n 2 build/release/bench/turk_rd_bench --cells 100000 --repeats 3
#include "bench_timing.hpp"
#include "core/config.hpp"
#include "core/log.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/point_relaxation.hpp"
#include "geom/surface_cells.hpp"
#include "par/ghosted_vector.hpp"
#include "par/morton_partition.hpp"
#include "par/petsc_session.hpp"
#include "pipelines/turk_rd/cell_rd_solver.hpp"
#include "rd/random_substrate.hpp"
#include "rd/reaction_model.hpp"
#include "rd/turing_spots_model.hpp"

#include <mpi.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace {
using texsim::bench::max_over_ranks;
using texsim::bench::median;
using texsim::bench::peak_memory_mb;
using texsim::bench::timed;
using texsim::par::Comm;
namespace geom = texsim::geom;
namespace rd = texsim::rd;

struct BenchSettings {
  std::string mesh = "data/meshes/bunny00.off";
  std::int64_t cells = 100000;
  int repeats = 3;        ///< relaxations and tilings
  int steps = 200;        ///< reaction-diffusion steps per timed run
  int step_repeats = 5;   ///< timed runs of `steps` steps
  int warmup = 5;         ///< steps before timing
  double stream_mb = 200; ///< size of each STREAM array, whole job (split over ranks)
  int stream_repeats = 10;
  std::uint64_t seed = 1;
};

// Fig. 3 (c) of Bajaj, Zhang, Xu: Turk's spots with s = 0.05, as the turk_rd patterns test uses.
constexpr const char* kTuringYaml = "type: turing_spots\ns: 0.05\n";
constexpr double kDt = 1.0;

double median_time(const Comm& comm, int repeats, const std::function<void()>& work) {
  std::vector<double> seconds;
  for (int r = 0; r < repeats; ++r)
    seconds.push_back(max_over_ranks(comm, timed(comm, work)));
  return median(seconds);
}

double sum_over_ranks(const Comm& comm, double value) {
  double result = 0;
  MPI_Allreduce(&value, &result, 1, MPI_DOUBLE, MPI_SUM, comm.raw);
  return result;
}

struct StreamResult {
  double triad_GBps = 0;
  double copy_GBps = 0;
  double array_mb_per_rank = 0;
};

/// STREAM triad a = b + q c (and copy c = a) on every rank and thread at once over arrays of
/// `array_mb_job` MB each, split over the ranks: bytes counted as STREAM does (triad 24 per
/// element: two reads, one write; the write-allocate read is not counted), summed over ranks,
/// divided by the slowest rank's time (median of `repeats`, each `sweeps` sweeps). Arrays are
/// first touched by the threads that use them. Collective.

StreamResult stream(const Comm& comm, double array_mb_job, int repeats, int sweeps) {
  const std::size_t n =
      std::max<std::size_t>(1024, std::size_t(array_mb_job * 1e6 / 8.0 / double(comm.size)));
  const auto a = std::make_unique_for_overwrite<double[]>(n);
  const auto b = std::make_unique_for_overwrite<double[]>(n);
  const auto c = std::make_unique_for_overwrite<double[]>(n);
  const std::int64_t count = std::int64_t(n);
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i) {
    a[i] = 0.0;
    b[i] = 1.0;
    c[i] = 2.0;
  }
  const double q = 0.5;
  const auto triad = [&] {
    for (int sweep = 0; sweep < sweeps; ++sweep) {
#pragma omp parallel for schedule(static)
      for (std::int64_t i = 0; i < count; ++i)
        a[i] = b[i] + q * c[i];
    }
  };
  const auto copy = [&] {
    for (int sweep = 0; sweep < sweeps; ++sweep) {
#pragma omp parallel for schedule(static)
      for (std::int64_t i = 0; i < count; ++i)
        c[i] = a[i];
    }
  };
  triad(); // page faults and frequency ramp-up outside the timings
  const double triad_s = median_time(comm, repeats, triad);
  const double copy_s = median_time(comm, repeats, copy);
  // Keep the stores observable.
  double check = 0;
  for (std::size_t i = 0; i < n; i += 4096)
    check += a[i] + c[i];
  TEXSIM_VERIFY(std::isfinite(check), "stream arrays");
  const double job_elements = sum_over_ranks(comm, double(n)) * sweeps;
  return {24.0 * job_elements / triad_s / 1e9, 16.0 * job_elements / copy_s / 1e9,
          double(n) * 8.0 / 1e6};
}

/// Wall time of relaxed_surface_points() (median of `repeats`) and the report of the last run.
struct RelaxTiming {
  double total_s = 0;
  std::vector<double> totals_s;
  double iteration_s = 0; ///< median sweep over all runs
  double setup_s = 0;     ///< median placement + partition
  geom::RelaxationReport last;
};

RelaxTiming time_relaxation(const Comm& comm, const geom::DistributedTriangles& surface,
                            const BenchSettings& settings) {
  RelaxTiming timing;
  std::vector<double> sweeps, setups;
  for (int r = 0; r < settings.repeats; ++r) {
    geom::RelaxationReport report;
    geom::DistributedSurfacePoints points;
    timing.totals_s.push_back(max_over_ranks(comm, timed(comm, [&] {
                                               points = geom::relaxed_surface_points(
                                                   comm, surface, settings.cells, settings.seed,
                                                   geom::RelaxationSettings{}, &report);
                                             })));
    sweeps.insert(sweeps.end(), report.seconds_per_iteration.begin(),
                  report.seconds_per_iteration.end());
    setups.push_back(report.seconds_setup);
    timing.last = report;
  }
  timing.total_s = median(timing.totals_s);
  timing.iteration_s = median(sweeps);
  timing.setup_s = median(setups);
  return timing;
}

/// Local cell data as a ReactionModel reads it: ids and centres of the owned cells.
struct CellData {
  std::vector<std::int64_t> ids;
  std::vector<double> xyz;
};

CellData cell_data(const geom::SurfaceCells& cells) {
  CellData data;
  data.ids.assign(cells.ids().begin(), cells.ids().end());
  for (const auto& p : cells.points())
    data.xyz.insert(data.xyz.end(), p.position.data(), p.position.data() + 3);
  return data;
}

/// The Turing step fused by hand, row by row in CSR order, as a reference in the same run: the
/// solver's weights (abar / A_i) f_ij w_ij with f = 1, both species of a cell together in a
/// GhostedVector with the same ghost update, the reaction written out with the substrate beta read
/// from an array instead of drawn every step, the same operation order as the solver so the values
/// match bit for bit. With `morton_order` the owned cells are stored along a Morton curve of their
/// centres instead of by id (each row still sums its neighbours in id order, so the values do not
/// change): the stencil's neighbours then lie close in memory. Not a replacement for the solver: a
/// measuring stick.
class FusedTuringStep {
public:
  /// Collective.
  FusedTuringStep(const Comm& comm, const geom::SurfaceCells& cells,
                  const rd::TuringSpotsParameters& p, std::uint64_t seed, bool morton_order)
      : p_(p), n_(cells.owned_count()) {
    const auto& stencil = cells.neighbors();
    // position_[i]: storage slot of owned cell i (local index, id order).
    position_.resize(std::size_t(n_));
    std::vector<std::int32_t> order(static_cast<std::size_t>(n_));
    for (std::int32_t i = 0; i < n_; ++i)
      order[i] = i;
    if (morton_order) {
      std::vector<std::array<double, 3>> centres;
      for (const auto& point : cells.points())
        centres.push_back({point.position.x(), point.position.y(), point.position.z()});
      const std::vector<std::uint64_t> keys = texsim::par::morton_keys(centres);
      std::stable_sort(order.begin(), order.end(),
                       [&](std::int32_t a, std::int32_t b) { return keys[a] < keys[b]; });
    }
    for (std::int32_t k = 0; k < n_; ++k)
      position_[order[k]] = k;
    const auto slot = [&](std::int32_t local) { return local < n_ ? position_[local] : local; };

    const double mean_area = cells.surface_area() / double(cells.global_count());
    const rd::RandomSubstrate substrate(seed, p.beta_mean, p.beta_spread);
    offsets_.push_back(0);
    for (std::int32_t k = 0; k < n_; ++k) {
      const std::int32_t i = order[k];
      for (std::int64_t e = stencil.offsets[i]; e < stencil.offsets[i + 1]; ++e) {
        indices_.push_back(slot(stencil.indices[e]));
        weights_.push_back(mean_area / cells.areas()[i] * 1.0 * cells.couplings()[e]);
      }
      offsets_.push_back(std::int64_t(indices_.size()));
      beta_.push_back(substrate.at(cells.ids()[i]));
    }

    // Ghosts are other ranks' cells: their global block is their owner's storage slot.
    const auto& offsets = cells.rank_offsets();
    std::vector<int> counts(std::size_t(comm.size)), displacements(std::size_t(comm.size));
    for (int r = 0; r < comm.size; ++r) {
      counts[r] = int(offsets[r + 1] - offsets[r]);
      displacements[r] = int(offsets[r]);
    }
    std::vector<std::int32_t> all_positions(std::size_t(offsets.back()));
    MPI_Allgatherv(position_.data(), n_, MPI_INT32_T, all_positions.data(), counts.data(),
                   displacements.data(), MPI_INT32_T, comm.raw);
    std::vector<std::int32_t> ghosts;
    for (const std::int32_t block : cells.ghost_blocks()) {
      const int owner =
          int(std::upper_bound(offsets.begin(), offsets.end(), block) - offsets.begin()) - 1;
      ghosts.push_back(std::int32_t(offsets[owner]) + all_positions[block]);
    }
    current_ = std::make_unique<texsim::par::GhostedVector>(comm, n_, ghosts, 2);
    next_ = std::make_unique<texsim::par::GhostedVector>(comm, n_, ghosts, 2);
    std::vector<double> initial(2 * std::size_t(n_));
    for (std::int32_t k = 0; k < n_; ++k) {
      initial[2 * std::size_t(k)] = p.initial_a;
      initial[2 * std::size_t(k) + 1] = p.initial_b;
    }
    current_->set_owned(initial);
  }

  /// One explicit step of `dt` (the solver's substep when dt exceeds its stability limit).
  /// Collective.
  void step(double dt) {
    const auto cur = current_->local();
    const auto next = next_->owned();
    const std::int64_t* offsets = offsets_.data();
    const std::int32_t* indices = indices_.data();
    const double* weights = weights_.data();
    const double s = p_.s, da = p_.diffusion_a, db = p_.diffusion_b;
#pragma omp parallel for schedule(static)
    for (std::int32_t k = 0; k < n_; ++k) {
      const double a = cur[2 * std::size_t(k)], b = cur[2 * std::size_t(k) + 1];
      double la = 0.0, lb = 0.0;
      for (std::int64_t e = offsets[k]; e < offsets[k + 1]; ++e) {
        const double* other = &cur[2 * std::size_t(indices[e])];
        la += weights[e] * (other[0] - a);
        lb += weights[e] * (other[1] - b);
      }
      const double rate_a = da * la + (-s * b) * a + 16.0 * s;
      const double rate_b = db * lb + (s * (a - 1.0)) * b + (-s * beta_[k]);
      next[2 * std::size_t(k)] = std::max(a + dt * rate_a, 0.0);
      next[2 * std::size_t(k) + 1] = std::max(b + dt * rate_b, 0.0);
    }
    std::swap(current_, next_);
    current_->update_ghosts();
  }

  /// Species `species` of owned cell i (local index in id order).
  double owned_value(std::int32_t i, int species) const {
    return current_->local()[2 * std::size_t(position_[i]) + std::size_t(species)];
  }

private:
  rd::TuringSpotsParameters p_;
  std::int32_t n_;
  std::vector<std::int32_t> position_;
  std::vector<std::int64_t> offsets_;
  std::vector<std::int32_t> indices_;
  std::vector<double> weights_, beta_;
  std::unique_ptr<texsim::par::GhostedVector> current_, next_;
};

/// Largest |solver - fused| over all cells and both species after `steps` steps from the initial
/// state (fused with or without the Morton storage order), maximum over ranks (0 when the fused
/// kernel reproduces the solver). Collective.
double fused_vs_solver(const Comm& comm, const geom::SurfaceCells& cells,
                       const rd::ReactionModel& model, const rd::TuringSpotsParameters& p,
                       std::uint64_t seed, int steps, bool morton_order) {
  const std::vector<double> scale(std::size_t(cells.owned_count()), 1.0);
  texsim::pipelines::turk_rd::CellRdSolver solver(comm, cells, model, scale, kDt);
  FusedTuringStep fused(comm, cells, p, seed, morton_order);
  for (int n = 0; n < steps; ++n) {
    solver.step(n * kDt);
    for (std::int64_t k = 0; k < solver.substeps(); ++k)
      fused.step(solver.substep_dt());
  }
  double worst = 0;
  for (int s = 0; s < 2; ++s) {
    const auto values = solver.owned_values(std::size_t(s));
    for (std::int32_t i = 0; i < cells.owned_count(); ++i)
      worst = std::max(worst, std::abs(values[i] - fused.owned_value(i, s)));
  }
  return max_over_ranks(comm, worst);
}

/// Seconds per call of `work` (median over `repeats` timings of `calls` calls, slowest rank).
double seconds_per_call(const Comm& comm, int repeats, int calls,
                        const std::function<void()>& work) {
  return median_time(comm, repeats,
                     [&] {
                       for (int n = 0; n < calls; ++n)
                         work();
                     }) /
         calls;
}

/// The model's coefficients of every owned cell, in the solver's blocks of 256 cells on all
/// threads (one sweep is what a step evaluates), with the random substrate precomputed (as the
/// solver passes it) or, when `substrate` is empty, drawn from the ids on every call.
void coefficients_sweep(const rd::ReactionModel& model, const CellData& data,
                        std::span<const double> substrate,
                        const std::vector<std::vector<double>>& state) {
  constexpr std::int32_t kBlock = 256;
  const std::int32_t n = std::int32_t(data.ids.size());
#pragma omp parallel
  {
    std::vector<rd::SpeciesCoefficients> out;
    std::vector<std::span<const double>> spans(state.size());
#pragma omp for schedule(static)
    for (std::int32_t begin = 0; begin < n; begin += kBlock) {
      const std::size_t count = std::size_t(std::min(kBlock, n - begin));
      for (std::size_t s = 0; s < state.size(); ++s)
        spans[s] = std::span<const double>(state[s]).subspan(std::size_t(begin), count);
      model.coefficients(
          0.0, spans,
          {std::span(data.ids).subspan(std::size_t(begin), count),
           std::span(data.xyz).subspan(3 * std::size_t(begin), 3 * count),
           substrate.empty() ? substrate : substrate.subspan(std::size_t(begin), count)},
          out);
    }
  }
}

struct StepPieces {
  double coefficients_s = 0;       ///< the model's coefficients, substrate precomputed
  double coefficients_drawn_s = 0; ///< the same with the substrate drawn on every call
  double substrate_s = 0;          ///< the Philox draws of beta alone
  double ghost_update_s = 0;       ///< one ghost update of the two-species state
};

/// Times the pieces of a Turing step on `cells`, each per step. Collective.
StepPieces measure_step_pieces(const Comm& comm, const geom::SurfaceCells& cells,
                               const rd::ReactionModel& model, const rd::TuringSpotsParameters& p,
                               const BenchSettings& settings) {
  constexpr int kSweeps = 20;
  const CellData data = cell_data(cells);
  const std::int32_t n = cells.owned_count();
  StepPieces pieces;
  const std::vector<std::vector<double>> state(2, std::vector<double>(std::size_t(n), 4.0));
  const std::vector<double> precomputed = model.substrate({data.ids, data.xyz});
  pieces.coefficients_s = seconds_per_call(comm, settings.step_repeats, kSweeps, [&] {
    coefficients_sweep(model, data, precomputed, state);
  });
  pieces.coefficients_drawn_s = seconds_per_call(
      comm, settings.step_repeats, kSweeps, [&] { coefficients_sweep(model, data, {}, state); });
  const rd::RandomSubstrate substrate(settings.seed, p.beta_mean, p.beta_spread);
  std::vector<double> beta(static_cast<std::size_t>(n));
  pieces.substrate_s = seconds_per_call(comm, settings.step_repeats, kSweeps, [&] {
#pragma omp parallel for schedule(static)
    for (std::int32_t i = 0; i < n; ++i)
      beta[i] = substrate.at(data.ids[i]);
  });
  texsim::par::GhostedVector ghosted(comm, n, cells.ghost_blocks(), 2);
  pieces.ghost_update_s =
      seconds_per_call(comm, settings.step_repeats, kSweeps, [&] { ghosted.update_ghosts(); });
  return pieces;
}

BenchSettings parse_arguments(int argc, char** argv) {
  BenchSettings s;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const std::string value = argv[i + 1];
    if (flag == "--mesh")
      s.mesh = value;
    else if (flag == "--cells")
      s.cells = std::stoll(value);
    else if (flag == "--repeats")
      s.repeats = std::stoi(value);
    else if (flag == "--steps")
      s.steps = std::stoi(value);
    else if (flag == "--step-repeats")
      s.step_repeats = std::stoi(value);
    else if (flag == "--warmup")
      s.warmup = std::stoi(value);
    else if (flag == "--stream-mb")
      s.stream_mb = std::stod(value);
    else if (flag == "--stream-repeats")
      s.stream_repeats = std::stoi(value);
    else if (flag == "--seed")
      s.seed = std::stoull(value);
  }
  return s;
}

} // namespace

int main(int argc, char** argv) {
  texsim::par::PetscSession session(argc, argv);
  const Comm comm = texsim::par::world();
  texsim::log::init(comm.rank, /*quiet=*/true); // stdout holds the JSON only
  const BenchSettings settings = parse_arguments(argc, argv);

  const bool fallback = !std::filesystem::exists(settings.mesh);
  const geom::TriangleMesh mesh = fallback ? geom::icosphere(6) : geom::read_mesh(settings.mesh);
  // Each rank keeps its share of the triangles, as in turk_rd.
  const auto surface = geom::DistributedTriangles::from_replicated(comm, mesh);

  // Turk's relaxation alone, then the whole tiling; the last tiling carries the solver.
  const RelaxTiming relax = time_relaxation(comm, surface, settings);
  geom::SurfaceCellsSettings cell_settings;
  cell_settings.count = settings.cells;
  std::unique_ptr<geom::SurfaceCells> cells;
  std::vector<double> retile_s, retile_relax_s;
  for (int r = 0; r < settings.repeats; ++r) {
    cells.reset();
    retile_s.push_back(max_over_ranks(comm, timed(comm, [&] {
                                        cells = std::make_unique<geom::SurfaceCells>(
                                            comm, surface, settings.seed, cell_settings);
                                      })));
    const auto& report = cells->relaxation();
    double relaxation = report.seconds_setup;
    for (const double s : report.seconds_per_iteration)
      relaxation += s;
    retile_relax_s.push_back(relaxation);
  }
  const double tiling_memory_mb = peak_memory_mb(comm);

  // Stencil size: the real mean neighbour count decides the bytes per update.
  const auto& stencil = cells->neighbors();
  const double neighbours_total = sum_over_ranks(comm, double(stencil.indices.size()));
  const double mean_neighbours = neighbours_total / double(cells->global_count());
  const double ghosts_total = sum_over_ranks(comm, double(cells->ghost_blocks().size()));

  auto config = texsim::ConfigDocument::parse(kTuringYaml, "turk_rd_bench");
  const auto model = rd::make_reaction_model(config.root(), settings.seed);
  rd::TuringSpotsParameters turing;
  turing.s = 0.05;

  // The solver and the two fused kernels: warm-up steps, then --step-repeats runs of --steps
  // steps each, the three interleaved so that a change of load on the shared machine hits them
  // alike.
  const std::vector<double> scale(std::size_t(cells->owned_count()), 1.0);
  texsim::pipelines::turk_rd::CellRdSolver solver(comm, *cells, *model, scale, kDt);
  FusedTuringStep fused(comm, *cells, turing, settings.seed, false);
  FusedTuringStep fused_morton(comm, *cells, turing, settings.seed, true);
  // The fused kernels take the solver's substeps, so both do the same work per step.
  const auto fused_step = [&](FusedTuringStep& kernel) {
    for (std::int64_t k = 0; k < solver.substeps(); ++k)
      kernel.step(solver.substep_dt());
  };
  double t = 0;
  for (int n = 0; n < settings.warmup; ++n, t += kDt) {
    solver.step(t);
    fused_step(fused);
    fused_step(fused_morton);
  }
  std::vector<double> run_s, fused_run_s, fused_morton_run_s;
  const auto time_run = [&](const std::function<void()>& step) {
    return max_over_ranks(comm, timed(comm, [&] {
                            for (int n = 0; n < settings.steps; ++n)
                              step();
                          }));
  };
  for (int r = 0; r < settings.step_repeats; ++r) {
    run_s.push_back(time_run([&] {
      solver.step(t);
      t += kDt;
    }));
    fused_run_s.push_back(time_run([&] { fused_step(fused); }));
    fused_morton_run_s.push_back(time_run([&] { fused_step(fused_morton); }));
  }
  const double solver_run_s = median(run_s);
  const double step_s = solver_run_s / settings.steps;
  const double cells_global = double(cells->global_count());
  const double cell_updates_per_s = cells_global * settings.steps / solver_run_s;
  bool finite = true;
  for (std::size_t s = 0; s < solver.species_count(); ++s)
    for (const double v : solver.owned_values(s))
      finite = finite && std::isfinite(v);
  const bool all_finite = max_over_ranks(comm, finite ? 0.0 : 1.0) == 0.0;
  double b_min = std::numeric_limits<double>::infinity(), b_max = -b_min;
  for (const double v : solver.owned_values(1)) {
    b_min = std::min(b_min, v);
    b_max = std::max(b_max, v);
  }
  b_max = max_over_ranks(comm, b_max);
  b_min = -max_over_ranks(comm, -b_min);

  // What a step is made of, each piece per step (median, slowest rank).
  const int check_steps = 20;
  const double fused_max_diff =
      fused_vs_solver(comm, *cells, *model, turing, settings.seed, check_steps, false);
  const double fused_morton_max_diff =
      fused_vs_solver(comm, *cells, *model, turing, settings.seed, check_steps, true);
  const StepPieces pieces = measure_step_pieces(comm, *cells, *model, turing, settings);

  // The bound: bytes a cell update must move at least, at the measured sustainable bandwidth.
  const StreamResult dram = stream(comm, settings.stream_mb, settings.stream_repeats, 1);
  const double bytes_per_update = 2 * 8 * 2 + 8 + mean_neighbours * (4 + 8);
  const double bound_cells_per_s = dram.triad_GBps * 1e9 / bytes_per_update;
  // The same triad on arrays as large as the step's working set (state twice, stencil, weights,
  // ids, centres): the rate the step could reach if it stays in the last-level cache.
  const double working_set_mb =
      sum_over_ranks(comm, double(cells->owned_count()) * (2 * 2 * 8 + 8 + 8 + 24) +
                               double(stencil.indices.size()) * (4 + 8)) /
      1e6;
  const StreamResult cache = stream(comm, working_set_mb / 3.0, settings.stream_repeats, 20);
  const double memory_mb = peak_memory_mb(comm);

  if (comm.is_root()) {
    const auto& quality = cells->quality();
    const nlohmann::json result = {
        {"benchmark", "turk_rd"},
        {"ranks", comm.size},
        {"threads", omp_get_max_threads()},
        {"mesh", fallback ? std::string("icosphere(6)") : settings.mesh},
        {"mesh_fallback", fallback},
        {"mesh_note", fallback ? settings.mesh + " missing (scripts/fetch-data): used icosphere(6)"
                               : std::string("")},
        {"mesh_vertices", mesh.num_vertices()},
        {"mesh_triangles", mesh.triangles.size()},
        {"cells", cells->global_count()},
        {"seed", settings.seed},
        {"repeats", settings.repeats},
        {"relaxation",
         {{"iterations", geom::RelaxationSettings{}.iterations},
          {"total_s", relax.total_s},
          {"totals_s", relax.totals_s},
          {"iteration_s", relax.iteration_s},
          {"setup_s", relax.setup_s},
          {"radius", relax.last.radius},
          {"max_halo_points", relax.last.max_halo_points},
          {"mean_move_last", relax.last.mean_move_per_iteration.empty()
                                 ? 0.0
                                 : relax.last.mean_move_per_iteration.back()}}},
        {"tiling",
         {{"total_s", median(retile_s)},
          {"totals_s", retile_s},
          {"relaxation_s", median(retile_relax_s)},
          {"voronoi_and_stencil_s", median(retile_s) - median(retile_relax_s)},
          {"surface_area", cells->surface_area()},
          {"spacing", cells->spacing()},
          {"mean_neighbours", mean_neighbours},
          {"ghosts_total", ghosts_total},
          {"edge_cut", quality.edge_cut},
          {"imbalance", quality.imbalance},
          {"ghosts_max", quality.ghosts_max}}},
        {"solver",
         {{"model", "turing_spots s=0.05"},
          {"dt", kDt},
          {"max_stable_dt", solver.max_stable_dt()},
          {"substeps", solver.substeps()},
          {"warmup_steps", settings.warmup},
          {"steps", settings.steps},
          {"step_repeats", settings.step_repeats},
          {"runs_s", run_s},
          {"best_cell_updates_per_s",
           cells_global * settings.steps / *std::min_element(run_s.begin(), run_s.end())},
          {"step_s", step_s},
          {"cell_updates_per_s", cell_updates_per_s},
          {"finite", all_finite},
          {"b_range", {b_min, b_max}}}},
        {"step_pieces",
         {{"coefficients_s", pieces.coefficients_s},
          {"coefficients_drawn_s", pieces.coefficients_drawn_s},
          {"substrate_philox_s", pieces.substrate_s},
          {"ghost_update_s", pieces.ghost_update_s},
          {"rest_s", step_s - pieces.coefficients_s - pieces.ghost_update_s},
          {"fused_step_s", median(fused_run_s) / settings.steps},
          {"fused_cell_updates_per_s", cells_global * settings.steps / median(fused_run_s)},
          {"fused_check_steps", check_steps},
          {"fused_max_abs_diff", fused_max_diff},
          {"fused_morton_step_s", median(fused_morton_run_s) / settings.steps},
          {"fused_morton_cell_updates_per_s",
           cells_global * settings.steps / median(fused_morton_run_s)},
          {"fused_morton_max_abs_diff", fused_morton_max_diff},
          {"fused_note", "bench-side kernel: solver's layout, weights and ghost update; Turing "
                         "reaction inline, beta from an array (+8 B per cell); morton: owned "
                         "cells stored along a Morton curve instead of by id"}}},
        {"stream_GBps", dram.triad_GBps},
        {"stream_copy_GBps", dram.copy_GBps},
        {"stream_array_mb_per_rank", dram.array_mb_per_rank},
        {"stream_working_set_GBps", cache.triad_GBps},
        {"working_set_mb", working_set_mb},
        {"bytes_per_update", bytes_per_update},
        {"byte_model",
         "own a,b read + written (2*8*2 B) + CSR offset 8 B + per neighbour 4 B index + 8 B "
         "weight (mean neighbours from cells.neighbors()); neighbour values cached; ids, centres, "
         "frozen flags and write-allocate not counted"},
        {"bandwidth_bound_cells_per_s", bound_cells_per_s},
        {"bandwidth_fraction", cell_updates_per_s / bound_cells_per_s},
        {"cache_bound_cells_per_s", cache.triad_GBps * 1e9 / bytes_per_update},
        {"vm_hwm_mb_after_tiling", tiling_memory_mb},
        {"vm_hwm_mb_max", memory_mb}};
    std::cout << result.dump() << std::endl;
  }
  return 0;
}
