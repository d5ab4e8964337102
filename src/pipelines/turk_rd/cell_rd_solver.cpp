#include "pipelines/turk_rd/cell_rd_solver.hpp"

#include "core/error.hpp"
#include "rd/turing_spots_model.hpp"

#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <type_traits>

namespace texsim::pipelines::turk_rd {
namespace {
/// Cells per reaction block: the block's species values and coefficients stay in L1/L2 cache.
constexpr std::int32_t kBlock = 256;
/// Cells summed side by side: their independent sums hide the latency of each add chain and of
/// the neighbour gathers (one cell's sum is a serial chain of about six dependent adds). With two
/// species a lane is one 16-byte register; 4 lanes ran at 2.64e8 cell updates/s at -n 2 on the
/// bunny bench, 8 at 2.40e8 (the accumulators and own values spill), 2 at 2.56e8.
constexpr std::int32_t kLanes = 4;
static_assert(kBlock % kLanes == 0);

/// Adds w (c_j - c_i) over the `width` slots of one lane group (see build_lane_groups) into
/// sum, slot by slot, so each species' sum keeps the same order and bits at any vector width.
template <int Species>
void sum_lane_group(const double* current, const std::int32_t* first_value, const double* weight,
                    std::int32_t width, const double (&own)[kLanes][Species],
                    double (&sum)[kLanes][Species]) {
  if constexpr (Species == 2) {
    // Both species of a cell sit side by side: one 16-byte load, subtract, multiply and add
    // per neighbour, where the compiler's own vectorisation across lanes shuffles scalars.
    using Pair = double __attribute__((vector_size(16)));
    Pair own_pair[kLanes], sum_pair[kLanes];
    for (std::int32_t lane = 0; lane < kLanes; ++lane) {
      own_pair[lane] = Pair{own[lane][0], own[lane][1]};
      sum_pair[lane] = Pair{0.0, 0.0};
    }
    for (std::int32_t k = 0; k < width; ++k)
      for (std::int32_t lane = 0; lane < kLanes; ++lane) {
        Pair other;
        std::memcpy(&other, &current[first_value[k * kLanes + lane]], sizeof(Pair));
        sum_pair[lane] += weight[k * kLanes + lane] * (other - own_pair[lane]);
      }
    for (std::int32_t lane = 0; lane < kLanes; ++lane) {
      sum[lane][0] = sum_pair[lane][0];
      sum[lane][1] = sum_pair[lane][1];
    }
  } else {
    for (std::int32_t lane = 0; lane < kLanes; ++lane)
      for (int s = 0; s < Species; ++s)
        sum[lane][s] = 0.0;
    for (std::int32_t k = 0; k < width; ++k)
      for (std::int32_t lane = 0; lane < kLanes; ++lane) {
        const double* other = &current[first_value[k * kLanes + lane]];
        const double w = weight[k * kLanes + lane];
        for (int s = 0; s < Species; ++s)
          sum[lane][s] += w * (other[s] - own[lane][s]);
      }
  }
}
} // namespace

CellRdSolver::CellRdSolver(const par::Comm& comm, const geom::SurfaceCells& cells,
                           const rd::ReactionModel& model, std::span<const double> diffusion_scale,
                           double dt, double stability_safety)
    : comm_(comm), cells_(cells), model_(model), names_(model.species()), dt_(dt), substep_dt_(dt),
      frozen_(std::size_t(cells.owned_count()), 0) {
  TEXSIM_VERIFY(stability_safety > 0 && stability_safety <= 1,
                "stability safety " << stability_safety << " outside (0, 1]");
  const std::int32_t n = cells.owned_count();
  const int species = int(names_.size());
  TEXSIM_VERIFY(diffusion_scale.size() == std::size_t(n), "diffusion scale has "
                                                              << diffusion_scale.size()
                                                              << " values for " << n << " cells");
  current_ = std::make_unique<par::GhostedVector>(comm, n, cells.ghost_blocks(), species);
  next_ = std::make_unique<par::GhostedVector>(comm, n, cells.ghost_blocks(), species);

  // Diffusion scale of the neighbours (owned or ghost) through the same ghost layer.
  par::GhostedVector scale(comm, n, cells.ghost_blocks(), 1);
  scale.set_owned(diffusion_scale);
  const double mean_area = cells.surface_area() / double(cells.global_count());
  const auto& stencil = cells.neighbors();
  weights_.resize(stencil.indices.size());
  for (std::int32_t i = 0; i < n; ++i)
    for (std::int64_t e = stencil.offsets[i]; e < stencil.offsets[i + 1]; ++e) {
      const double f = 0.5 * (scale.local()[i] + scale.local()[stencil.indices[e]]);
      weights_[e] = mean_area / cells.areas()[i] * f * cells.couplings()[e];
    }

  build_lane_groups();
  ids_.assign(cells.ids().begin(), cells.ids().end());
  for (const auto& p : cells.points())
    xyz_.insert(xyz_.end(), p.position.data(), p.position.data() + 3);

  // The rates and bounds do not depend on the state: read them from one evaluation.
  std::vector<rd::SpeciesCoefficients> probe;
  const std::vector<std::int64_t> probe_id{0};
  const std::vector<double> probe_xyz{0, 0, 0};
  const auto probe_initial = model.initial_state({probe_id, probe_xyz});
  std::vector<std::span<const double>> probe_state;
  for (const auto& values : probe_initial)
    probe_state.emplace_back(values);
  model.coefficients(0.0, probe_state, {probe_id, probe_xyz}, probe);
  for (int s = 0; s < species; ++s) {
    rates_.push_back(probe[s].diffusion);
    lower_bounds_.push_back(model.lower_bound(std::size_t(s)));
  }

  double row_sum_max = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    double row_sum = 0;
    for (std::int64_t e = stencil.offsets[i]; e < stencil.offsets[i + 1]; ++e)
      row_sum += weights_[e];
    row_sum_max = std::max(row_sum_max, row_sum);
  }
  MPI_Allreduce(MPI_IN_PLACE, &row_sum_max, 1, MPI_DOUBLE, MPI_MAX, comm.raw);
  const double fastest = *std::max_element(rates_.begin(), rates_.end());
  max_stable_dt_ = fastest > 0 && row_sum_max > 0 ? 1.0 / (fastest * row_sum_max)
                                                  : std::numeric_limits<double>::infinity();
  // Every rank holds the same limit (reduced above), so every rank takes the same substeps.
  if (dt > max_stable_dt_) {
    substeps_ = std::int64_t(std::ceil(dt / (stability_safety * max_stable_dt_)));
    substep_dt_ = dt / double(substeps_);
  }

  substrate_ = model.substrate({ids_, xyz_});
  turing_spots_ = model.as_turing_spots();
  scratch_.resize(std::size_t(omp_get_max_threads()));
  for (auto& scratch : scratch_) {
    scratch.state.assign(std::size_t(species), std::vector<double>(kBlock));
    scratch.state_spans.resize(std::size_t(species));
    scratch.laplacian.resize(std::size_t(species));
  }
  const auto initial = model.initial_state({ids_, xyz_});
  TEXSIM_VERIFY(initial.size() == names_.size(), "model gave " << initial.size()
                                                               << " initial fields for "
                                                               << names_.size() << " species");
  auto owned = current_->owned();
  for (std::int32_t i = 0; i < n; ++i)
    for (int s = 0; s < species; ++s)
      owned[std::size_t(i) * species + s] = initial[s][i];
  current_->update_ghosts();
}

void CellRdSolver::build_lane_groups() {
  // The cells of each block are taken by degree (stable), kLanes at a time: a group's lanes then
  // have equal degrees nearly everywhere and little padding (17 % of the slots with groups of
  // consecutive cells on the bunny). Each cell's sum is its own, so the grouping leaves the bits.
  // Slot k of lane l of group g is entry group_offsets_[g] + k kLanes + l. Lists are padded to
  // the group's largest degree with the cell itself and weight 0: 0 * (c_i - c_i) adds +0, so
  // each sum keeps its bits; lanes past the block's end repeat the group's first cell and
  // are not stored. A slot holds the neighbour's first value in the species-interleaved state
  // (index x species), which the kernel adds to the base pointer with a scaled address.
  const std::int32_t n = cells_.owned_count();
  const auto& stencil = cells_.neighbors();
  const auto species = std::int64_t(names_.size());
  TEXSIM_VERIFY((std::int64_t(n) + std::int64_t(cells_.ghost_blocks().size())) * species <=
                    std::numeric_limits<std::int32_t>::max(),
                "a rank's " << n << " cells and ghosts of " << species
                            << " species overflow 32-bit value offsets");
  const auto degree = [&](std::int32_t i) { return stencil.offsets[i + 1] - stencil.offsets[i]; };
  group_offsets_.assign(1, 0);
  group_widths_.clear();
  group_cells_.clear();
  for (std::int32_t begin = 0; begin < n; begin += kBlock) {
    const std::int32_t end = std::min(n, begin + kBlock);
    std::vector<std::int32_t> order(std::size_t(end - begin));
    std::iota(order.begin(), order.end(), begin);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::int32_t a, std::int32_t b) { return degree(a) < degree(b); });
    for (std::size_t first = 0; first < order.size(); first += kLanes) {
      std::int32_t lane_cells[kLanes];
      for (std::int32_t lane = 0; lane < kLanes; ++lane)
        lane_cells[lane] = first + lane < order.size() ? order[first + lane] : order[first];
      std::int64_t width = 0;
      for (const std::int32_t i : lane_cells)
        width = std::max(width, degree(i));
      for (std::int64_t k = 0; k < width; ++k)
        for (const std::int32_t i : lane_cells) {
          const bool real = k < degree(i);
          group_first_value_.push_back(
              std::int32_t(species * (real ? stencil.indices[stencil.offsets[i] + k] : i)));
          group_weight_.push_back(real ? weights_[stencil.offsets[i] + k] : 0.0);
        }
      group_cells_.insert(group_cells_.end(), lane_cells, lane_cells + kLanes);
      group_widths_.push_back(std::int32_t(width));
      group_offsets_.push_back(std::int64_t(group_first_value_.size()));
    }
  }
}

std::vector<double> CellRdSolver::owned_values(std::size_t s) const {
  const std::size_t species = names_.size();
  const auto local = current_->local();
  std::vector<double> values(std::size_t(cells_.owned_count()));
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = local[i * species + s];
  return values;
}

void CellRdSolver::set_owned_values(std::size_t s, std::span<const double> owned_values) {
  const std::size_t species = names_.size();
  TEXSIM_VERIFY(owned_values.size() == std::size_t(cells_.owned_count()),
                "set_owned_values: " << owned_values.size() << " values for "
                                     << cells_.owned_count() << " cells");
  auto owned = current_->owned();
  for (std::size_t i = 0; i < owned_values.size(); ++i)
    owned[i * species + s] = owned_values[i];
  current_->update_ghosts();
}

void CellRdSolver::set_frozen(std::vector<char> frozen) {
  TEXSIM_VERIFY(frozen.size() == frozen_.size(),
                "set_frozen: " << frozen.size() << " flags for " << frozen_.size() << " cells");
  frozen_ = std::move(frozen);
}

std::size_t CellRdSolver::frozen_count() const {
  return std::size_t(std::count(frozen_.begin(), frozen_.end(), 1));
}

template <int Species, typename Pointwise>
void CellRdSolver::update_block(std::int32_t begin, std::int32_t count, double t,
                                BlockScratch& scratch, const Pointwise* pointwise) const {
  constexpr bool kPointwise = !std::is_void_v<Pointwise>;
  const std::size_t species = Species > 0 ? std::size_t(Species) : names_.size();
  const auto current = current_->local();
  const auto next = next_->owned();
  const auto& stencil = cells_.neighbors();
  auto& coefficients = scratch.coefficients;
  if constexpr (!kPointwise)
    evaluate_block(begin, count, t, scratch);
  if constexpr (Species == 0) {
    // Run-time species count (user systems): one cell at a time along its CSR row.
    for (std::int32_t k = 0; k < count; ++k) {
      const std::int32_t i = begin + k;
      const double* own = &current[std::size_t(i) * species];
      double* out = &next[std::size_t(i) * species];
      if (frozen_[i]) {
        std::copy(own, own + species, out);
        continue;
      }
      double* sum = scratch.laplacian.data();
      std::fill(sum, sum + species, 0.0);
      for (std::int64_t e = stencil.offsets[i]; e < stencil.offsets[i + 1]; ++e) {
        const double* other = &current[std::size_t(stencil.indices[e]) * species];
        for (std::size_t s = 0; s < species; ++s)
          sum[s] += weights_[e] * (other[s] - own[s]);
      }
      for (std::size_t s = 0; s < species; ++s) {
        const double rate =
            rates_[s] * sum[s] + coefficients[s].linear[k] * own[s] + coefficients[s].source[k];
        out[s] = std::max(own[s] + substep_dt_ * rate, lower_bounds_[s]);
      }
    }
  } else {
    // Locals, not members: the stores to `next` could alias members, which would be reloaded.
    const double dt = substep_dt_;
    double rates[Species], lower_bounds[Species];
    for (int s = 0; s < Species; ++s) {
      rates[s] = rates_[s];
      lower_bounds[s] = lower_bounds_[s];
    }
    for (std::int32_t first = begin; first < begin + count; first += kLanes) {
      const std::int32_t g = first / kLanes;
      const std::int32_t lanes = std::min(kLanes, begin + count - first);
      const std::int32_t* lane_cells = &group_cells_[std::size_t(first)];
      double own[kLanes][Species], sum[kLanes][Species];
      for (std::int32_t lane = 0; lane < kLanes; ++lane)
        for (int s = 0; s < Species; ++s)
          own[lane][s] = current[std::size_t(lane_cells[lane]) * Species + s];
      sum_lane_group<Species>(current.data(), &group_first_value_[std::size_t(group_offsets_[g])],
                              &group_weight_[std::size_t(group_offsets_[g])], group_widths_[g], own,
                              sum);
      for (std::int32_t lane = 0; lane < lanes; ++lane) {
        const std::int32_t i = lane_cells[lane];
        const std::int32_t k = i - begin;
        double* out = &next[std::size_t(i) * Species];
        if (frozen_[i]) {
          for (int s = 0; s < Species; ++s)
            out[s] = own[lane][s];
          continue;
        }
        double linear[Species], source[Species];
        if constexpr (kPointwise)
          pointwise->vertex_coefficients(own[lane][0], own[lane][1], substrate_[i], linear, source);
        for (int s = 0; s < Species; ++s) {
          const double c2 = kPointwise ? linear[s] : coefficients[s].linear[k];
          const double c3 = kPointwise ? source[s] : coefficients[s].source[k];
          const double rate = rates[s] * sum[lane][s] + c2 * own[lane][s] + c3;
          out[s] = std::max(own[lane][s] + dt * rate, lower_bounds[s]);
        }
      }
    }
  }
}

void CellRdSolver::evaluate_block(std::int32_t begin, std::int32_t count, double t,
                                  BlockScratch& scratch) const {
  const std::size_t species = names_.size();
  const auto current = current_->local();
  for (std::size_t s = 0; s < species; ++s) {
    for (std::int32_t k = 0; k < count; ++k)
      scratch.state[s][k] = current[std::size_t(begin + k) * species + s];
    scratch.state_spans[s] = std::span<const double>(scratch.state[s]).first(std::size_t(count));
  }
  const auto substrate =
      substrate_.empty() ? std::span<const double>()
                         : std::span(substrate_).subspan(std::size_t(begin), std::size_t(count));
  model_.coefficients(t, scratch.state_spans,
                      {std::span(ids_).subspan(std::size_t(begin), std::size_t(count)),
                       std::span(xyz_).subspan(3 * std::size_t(begin), 3 * std::size_t(count)),
                       substrate},
                      scratch.coefficients);
}

void CellRdSolver::step(double t) {
  for (std::int64_t k = 0; k < substeps_; ++k)
    substep(t + double(k) * substep_dt_);
}

void CellRdSolver::substep(double t) {
  const std::int32_t n = cells_.owned_count();
  const std::size_t species = names_.size();
  const std::int32_t blocks = (n + kBlock - 1) / kBlock;
#pragma omp parallel if (model_.thread_safe())
  {
    BlockScratch& scratch = scratch_[std::size_t(omp_get_thread_num())];
#pragma omp for schedule(static)
    for (std::int32_t b = 0; b < blocks; ++b) {
      const std::int32_t begin = b * kBlock;
      const std::int32_t count = std::min(kBlock, n - begin);
      switch (species) {
      case 2:
        if (turing_spots_)
          update_block<2>(begin, count, t, scratch, turing_spots_);
        else
          update_block<2>(begin, count, t, scratch);
        break;
      case 5:
        update_block<5>(begin, count, t, scratch);
        break;
      default:
        update_block<0>(begin, count, t, scratch);
      }
    }
  }
  std::swap(current_, next_);
  current_->update_ghosts();
}

double CellRdSolver::integral(std::size_t s) const {
  const auto values = owned_values(s);
  double local = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i)
    local += cells_.areas()[i] * values[i];
  double total = 0.0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm_.raw);
  return total;
}

} // namespace texsim::pipelines::turk_rd
