#pragma once
/// Checks made once the config is read and before any work: the memory the run needs per rank,
/// and the PETSc options given on the command line or under `petsc:`.
#include "core/memory_budget.hpp"
#include "par/comm.hpp"

#include <string>

namespace texsim::app {

/// Ranks of `comm` that share this rank's node (MPI_COMM_TYPE_SHARED). Collective.
int ranks_on_node(const par::Comm& comm);

/// Refuses the run (InputError on every rank, naming the key) when `estimate`, plus what the
/// libraries take, exceeds the memory of the node divided among its ranks (core/memory_budget).
/// Collective.
void require_memory_per_rank(const par::Comm& comm, const MemoryEstimate& estimate);

/// "memory: about 1.2 GiB per rank at 2 ranks (key: detail); 11 GiB available per rank
/// (MemAvailable)", for `texsim validate`. Collective.
std::string memory_summary(const par::Comm& comm, const MemoryEstimate& estimate);

/// Sets up a PETSc Krylov solver from the options database, as every solver of a run will, and
/// turns an error (an unknown -ksp_type, a value that is not a number, ...) into an InputError
/// on every rank: "PETSc options: Unknown KSP type: cgg ...". Collective.
void check_petsc_options(const par::Comm& comm);

} // namespace texsim::app
