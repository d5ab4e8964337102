#include "par/checkpoint_clock.hpp"

#include "core/stop_signal.hpp"

#include <mpi.h>

namespace texsim::par {

double default_checkpoint_minutes(const Comm& comm) {
  MPI_Comm node = MPI_COMM_NULL;
  MPI_Comm_split_type(comm.raw, MPI_COMM_TYPE_SHARED, comm.rank, MPI_INFO_NULL, &node);
  int node_rank = 0;
  MPI_Comm_rank(node, &node_rank);
  MPI_Comm_free(&node);
  int leader = node_rank == 0 ? 1 : 0, nodes = 0;
  MPI_Allreduce(&leader, &nodes, 1, MPI_INT, MPI_SUM, comm.raw);
  return nodes > 1 ? 30.0 : 60.0;
}

CheckpointClock::CheckpointClock(const Comm& comm, std::int64_t every_steps,
                                 std::optional<double> minutes)
    : comm_(comm), every_steps_(every_steps),
      seconds_(minutes.value_or(default_checkpoint_minutes(comm)) * 60.0),
      last_checkpoint_s_(MPI_Wtime()) {}

CheckpointClock::Decision CheckpointClock::after_step(std::int64_t done) {
  // Only rank 0's clock counts, so all ranks agree even when their clocks drift.
  const double now = MPI_Wtime();
  int local[2] = {received_stop_signal(),
                  comm_.is_root() && seconds_ > 0 && now - last_checkpoint_s_ >= seconds_ ? 1 : 0};
  int global[2] = {0, 0};
  MPI_Allreduce(local, global, 2, MPI_INT, MPI_MAX, comm_.raw);
  Decision decision;
  decision.signal_number = global[0];
  decision.stop = global[0] != 0;
  decision.checkpoint =
      decision.stop || global[1] != 0 || (every_steps_ > 0 && done % every_steps_ == 0);
  if (decision.checkpoint)
    last_checkpoint_s_ = now;
  return decision;
}

int CheckpointClock::agreed_stop_signal() const {
  int local = received_stop_signal(), global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, comm_.raw);
  return global;
}

} // namespace texsim::par
