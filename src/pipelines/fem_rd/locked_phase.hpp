#pragma once
/// Fig. 5's pattern classes, measured. A forced oscillator locked at one quarter of the forcing
/// frequency has four stable phases (Lin et al., "Four-phase patterns in forced oscillatory
/// systems", Phys. Rev. E 62, 3790 (2000)): rotating four-phase spirals take all four, standing
/// two-phase patterns (labyrinths) two of them pi apart, a synchronised surface one. Over the
/// last `periods` response periods of the run (4 forcing periods each) every vertex accumulates
/// the Fourier coefficient of u at the response frequency omega_f / 4,
///   A_v = sum_n (u_v(t_n) - mean_v) e^(-i omega_f t_n / 4),
/// whose argument phi_v is the vertex's phase against the forcing. The order parameters
///   R_m = |sum_v e^(i m phi_v)| / vertices,  m = 1, 2, 4,
/// tell the classes apart: one phase (R1 near 1), two phases pi apart (R1 small, R2 near 1),
/// four phases pi/2 apart (R1 and R2 small, R4 near 1); the response amplitude
/// |A_v| / (window samples / 2) is the oscillation's amplitude at that frequency. Locking itself
/// shows as a phase that stands still: the mean change of phi_v from the window's first half to
/// its second (a response period each) is the drift, 0 for a locked response. The phases the
/// surface takes are counted as the peaks of a 30-degree histogram of phi_v.
#include "par/comm.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace texsim::pipelines::fem_rd {

class LockedPhase {
public:
  /// Sums per vertex and half window: u, u cos(w t), u sin(w t).
  static constexpr int kSums = 3;
  /// Largest drift (degrees per response period) of a response counted as locked.
  static constexpr double kLockedDriftDeg = 10;
  /// Smallest share of the vertices (a histogram peak and its larger neighbour) that counts as
  /// one of the surface's phases.
  static constexpr double kPeakFraction = 0.1;

  /// For a run of `steps` steps of `dt` forced at `forcing_omega` (> 0), on `owned_count`
  /// vertices. The window holds the last `periods` whole response periods (the whole run when
  /// it is shorter).
  LockedPhase(double forcing_omega, double dt, std::int64_t steps, std::int32_t owned_count,
              int periods = 2);

  /// Adds u (owned vertices) at the end of step `step` (time (step + 1) dt) when inside the
  /// window.
  void add(std::int64_t step, std::span<const double> owned_u);

  /// What a checkpoint keeps, one array over the owned vertices per dataset name: the sums and
  /// the window's first step (the same at every vertex), so that a restart whose run length
  /// moved the window can tell.
  std::vector<std::pair<std::string, std::vector<double>*>> checkpoint_columns();
  /// After a restart at step `start` from columns read back: when the checkpoint's window began
  /// elsewhere (the run length changed), the sums start afresh, at `start` if that is later than
  /// the window's start. Collective.
  void resume(const par::Comm& comm, std::int64_t start);

  /// Window, response frequency, drift and whether it is locked, R1, R2, R4, the mean response
  /// amplitude, the fraction of the vertices in each 30-degree bin of phase (from -180 degrees)
  /// and the number of phases the surface takes (peaks of that histogram; 0 when the response
  /// is not locked), the same bits for any number of ranks. Collective.
  nlohmann::json metrics(const par::Comm& comm) const;

private:
  double omega_ = 0; ///< response angular frequency, omega_f / 4
  double dt_ = 0;
  std::int64_t first_step_ = 0;     ///< first step whose end is in the window
  std::int64_t middle_step() const; ///< first step of the window's second half
  std::int64_t steps_ = 0;
  std::vector<std::vector<double>> sums_; ///< [half * kSums + sum][owned vertex]
  std::vector<double> stored_first_step_; ///< first_step_ at every owned vertex, for checkpoints
};

} // namespace texsim::pipelines::fem_rd
