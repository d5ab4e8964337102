#include "pipelines/fem_rd/locked_phase.hpp"

#include "core/error.hpp"
#include "par/reproducible_sum.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace texsim::pipelines::fem_rd {

LockedPhase::LockedPhase(double forcing_omega, double dt, std::int64_t steps,
                         std::int32_t owned_count, int periods)
    : omega_(forcing_omega / 4), dt_(dt), steps_(steps),
      sums_(2 * kSums, std::vector<double>(static_cast<std::size_t>(owned_count), 0.0)) {
  TEXSIM_VERIFY(forcing_omega > 0 && dt > 0 && periods >= 1, "locked phase: forcing omega "
                                                                 << forcing_omega << ", dt " << dt
                                                                 << ", periods " << periods);
  const double window = periods * 2 * std::numbers::pi / omega_;
  first_step_ = std::max<std::int64_t>(0, steps - std::llround(window / dt));
  stored_first_step_.assign(static_cast<std::size_t>(owned_count), double(first_step_));
}

std::vector<std::pair<std::string, std::vector<double>*>> LockedPhase::checkpoint_columns() {
  std::vector<std::pair<std::string, std::vector<double>*>> columns;
  const char* names[kSums] = {"u", "u_cos", "u_sin"};
  for (int half = 0; half < 2; ++half)
    for (int k = 0; k < kSums; ++k)
      columns.emplace_back("locked_phase_" + std::string(names[k]) + "_" + std::to_string(half),
                           &sums_[std::size_t(half * kSums + k)]);
  columns.emplace_back("locked_phase_window_start", &stored_first_step_);
  return columns;
}

void LockedPhase::resume(const par::Comm& comm, std::int64_t start) {
  int moved = std::any_of(stored_first_step_.begin(), stored_first_step_.end(),
                          [&](double s) { return s != double(first_step_); });
  MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_INT, MPI_MAX, comm.raw);
  if (moved != 0) {
    first_step_ = std::max(first_step_, start);
    for (auto& sum : sums_)
      std::fill(sum.begin(), sum.end(), 0.0);
  }
  stored_first_step_.assign(stored_first_step_.size(), double(first_step_));
}

std::int64_t LockedPhase::middle_step() const {
  return first_step_ + (steps_ - first_step_) / 2;
}

void LockedPhase::add(std::int64_t step, std::span<const double> owned_u) {
  if (step < first_step_ || step >= steps_)
    return;
  const double t = double(step + 1) * dt_;
  const double c = std::cos(omega_ * t), s = std::sin(omega_ * t);
  auto* sums = &sums_[step < middle_step() ? 0 : kSums];
  for (std::size_t v = 0; v < owned_u.size(); ++v) {
    sums[0][v] += owned_u[v];
    sums[1][v] += owned_u[v] * c;
    sums[2][v] += owned_u[v] * s;
  }
}

nlohmann::json LockedPhase::metrics(const par::Comm& comm) const {
  // Per half of the window: its samples and the sums of cos and sin over its times, which take
  // each vertex's mean out of its Fourier sum.
  struct Half {
    std::int64_t samples = 0;
    double cos_sum = 0, sin_sum = 0;
  };
  Half halves[2];
  for (std::int64_t step = first_step_; step < steps_; ++step) {
    Half& half = halves[step < middle_step() ? 0 : 1];
    ++half.samples;
    half.cos_sum += std::cos(omega_ * double(step + 1) * dt_);
    half.sin_sum += std::sin(omega_ * double(step + 1) * dt_);
  }
  const auto coefficient = [&](int h, std::size_t v) {
    const auto* sums = &sums_[std::size_t(h * kSums)];
    if (halves[h].samples == 0)
      return std::complex<double>();
    const double mean = sums[0][v] / double(halves[h].samples);
    return std::complex<double>(sums[1][v] - mean * halves[h].cos_sum,
                                -(sums[2][v] - mean * halves[h].sin_sum));
  };
  const std::int64_t samples = halves[0].samples + halves[1].samples;
  constexpr int kBins = 12; // of 30 degrees, from -180
  // Rows: cos and sin of m phi for m = 1, 2, 4; amplitude; cos and sin of the drift; bins.
  std::vector<std::vector<double>> terms(9 + kBins, std::vector<double>(sums_[0].size()));
  for (std::size_t v = 0; v < sums_[0].size(); ++v) {
    const std::complex<double> first = coefficient(0, v), second = coefficient(1, v);
    const double phase = std::arg(first + second);
    for (const int m : {1, 2, 4}) {
      const std::size_t row = m == 1 ? 0 : (m == 2 ? 2 : 4);
      terms[row][v] = std::cos(m * phase);
      terms[row + 1][v] = std::sin(m * phase);
    }
    terms[6][v] = std::abs(first + second) / (0.5 * double(samples));
    const double drift = std::arg(second * std::conj(first));
    terms[7][v] = std::cos(drift);
    terms[8][v] = std::sin(drift);
    const int bin = std::clamp(
        static_cast<int>(std::floor((phase + std::numbers::pi) / (2 * std::numbers::pi) * kBins)),
        0, kBins - 1);
    terms[9 + std::size_t(bin)][v] = 1.0;
  }
  const double vertices = par::reproducible_sum(comm, std::vector<double>(sums_[0].size(), 1.0));
  const auto mean_of = [&](std::size_t row) {
    return par::reproducible_sum(comm, terms[row]) / vertices;
  };
  const auto order = [&](std::size_t row) { return std::hypot(mean_of(row), mean_of(row + 1)); };
  const double r1 = order(0), r2 = order(2), r4 = order(4);
  // Per half of the window (a response period): 0 when the response is locked to the forcing.
  const double drift_deg = std::atan2(mean_of(8), mean_of(7)) * 180 / std::numbers::pi;
  const bool locked = std::abs(drift_deg) <= kLockedDriftDeg;
  std::vector<double> histogram(kBins);
  for (int bin = 0; bin < kBins; ++bin)
    histogram[std::size_t(bin)] = mean_of(9 + std::size_t(bin));
  // The phases the surface takes: peaks of the circular histogram (the first bin of a plateau)
  // that hold, with their larger neighbour, at least kPeakFraction of the vertices and stand at
  // least twice as high as the lower of the bins 60 degrees either side (an even spread of
  // phases has no peaks).
  const auto at = [&](int bin) { return histogram[std::size_t((bin + kBins) % kBins)]; };
  int phases = 0;
  for (int bin = 0; bin < kBins && locked; ++bin)
    if (at(bin) > at(bin - 1) && at(bin) >= at(bin + 1) &&
        at(bin) + std::max(at(bin - 1), at(bin + 1)) >= kPeakFraction &&
        at(bin) >= 2 * std::min(at(bin - 2), at(bin + 2)))
      ++phases;
  return {{"response_omega", omega_},
          {"window", {double(first_step_ + 1) * dt_, double(steps_) * dt_}},
          {"samples", samples},
          {"phase_drift_deg", drift_deg},
          {"locked", locked},
          {"order_1", r1},
          {"order_2", r2},
          {"order_4", r4},
          {"phases", phases},
          {"amplitude_mean", mean_of(6)},
          {"phase_histogram", histogram}};
}

} // namespace texsim::pipelines::fem_rd
