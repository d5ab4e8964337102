#pragma once
/// When a run writes a checkpoint and when it stops, decided the same way on every rank at a step
/// boundary: every `checkpoint.every` steps, every `checkpoint.minutes` of wall time (rank 0's
/// clock), and at once when any rank has received SIGTERM or SIGUSR1 (core/stop_signal.hpp), in
/// which case the run stops after that checkpoint with exit code 3.
#include "par/comm.hpp"

#include <cstdint>
#include <optional>

namespace texsim::par {

/// `checkpoint.minutes` when the config does not set it: 30 when the ranks span more than one
/// node (a cluster job, killed at its time limit), 60 on one node. Collective.
double default_checkpoint_minutes(const Comm& comm);

class CheckpointClock {
public:
  struct Decision {
    bool checkpoint = false; ///< write a checkpoint now
    bool stop = false;       ///< then stop: a stop signal arrived on some rank
    int signal_number = 0;   ///< the signal (the highest number received on any rank)
  };

  /// every_steps: 0 = no step cadence; minutes: 0 = no wall-clock cadence, unset = the default
  /// above. Starts the clock. Collective.
  CheckpointClock(const Comm& comm, std::int64_t every_steps, std::optional<double> minutes);

  /// Call on every rank after a step; `done` counts the steps finished. Collective (one small
  /// MPI_Allreduce). A checkpoint decision restarts the wall-clock cadence.
  Decision after_step(std::int64_t done);

  /// The stop signal received on any rank (0 when none), without the cadences: for checks inside
  /// a long step that can be abandoned. Collective (one small MPI_Allreduce).
  int agreed_stop_signal() const;

private:
  Comm comm_;
  std::int64_t every_steps_;
  double seconds_;
  double last_checkpoint_s_;
};

} // namespace texsim::par
