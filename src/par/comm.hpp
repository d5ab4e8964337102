#pragma once
/// The communicator a run works on, with its rank and size cached.
#include <mpi.h>

namespace texsim::par {

struct Comm {
  MPI_Comm raw = MPI_COMM_WORLD;
  int rank = 0;
  int size = 1;

  bool is_root() const { return rank == 0; }
  /// Blocks until every rank arrives. Collective.
  void barrier() const;
};

/// MPI_COMM_WORLD with its rank and size.
Comm world();

} // namespace texsim::par
