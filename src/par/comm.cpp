#include "par/comm.hpp"

namespace texsim::par {

void Comm::barrier() const {
  MPI_Barrier(raw);
}

Comm world() {
  Comm comm;
  MPI_Comm_rank(comm.raw, &comm.rank);
  MPI_Comm_size(comm.raw, &comm.size);
  return comm;
}

} // namespace texsim::par
