#pragma once
/// The warning a scheduler sends before it kills a job (SIGTERM from Slurm, PBS or mpirun; SIGUSR1
/// from `sbatch --signal=USR1@...`): the handler only records the signal, and the pipelines look
/// at it between steps (par::CheckpointClock), write a checkpoint and stop with exit code 3.
#include <stdexcept>
#include <string>

namespace texsim {

/// Exit code of a run that stopped on a signal after writing a checkpoint: "resubmit with
/// --restart". 0 = finished, 1 = internal error, 2 = bad input.
inline constexpr int kExitCheckpointed = 3;

/// Records SIGTERM and SIGUSR1 instead of dying on them. Call once, on every rank, before work.
void install_stop_signal_handlers();

/// The stop signal received since install_stop_signal_handlers() (0 when none). Not collective:
/// each rank sees only its own signals; par::CheckpointClock agrees on them.
int received_stop_signal();

/// Thrown on every rank by a pipeline that stopped after writing its checkpoint (`where` says at
/// which point, for the message); main() catches it, writes no summary.json and exits with
/// kExitCheckpointed.
class CheckpointedStop : public std::runtime_error {
public:
  CheckpointedStop(int signal_number, const std::string& where);
};

} // namespace texsim
