#include "app/preflight.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"

#include <petscksp.h>

namespace texsim::app {
namespace {

/// What a rank holds before any pipeline allocates: the libraries (PETSc, VTK, OpenVDB, HDF5)
/// and MPI's buffers (measured: 92 MiB peak RSS for the 2,560-triangle mesh_prep smoke run).
constexpr std::uint64_t kBaselineBytes = 128ull << 20;

MemoryEstimate with_baseline(MemoryEstimate estimate) {
  if (estimate.bytes > 0)
    estimate.bytes = saturating_add(estimate.bytes, kBaselineBytes);
  return estimate;
}

/// PETSc error handler that keeps the first (most specific) message of an error.
PetscErrorCode record_first_message(MPI_Comm, int, const char*, const char*, PetscErrorCode code,
                                    PetscErrorType type, const char* message, void* context) {
  auto& first = *static_cast<std::string*>(context);
  if (type == PETSC_ERROR_INITIAL && first.empty() && message != nullptr)
    first = message;
  return code;
}

} // namespace

int ranks_on_node(const par::Comm& comm) {
  MPI_Comm node = MPI_COMM_NULL;
  MPI_Comm_split_type(comm.raw, MPI_COMM_TYPE_SHARED, comm.rank, MPI_INFO_NULL, &node);
  int size = 1;
  MPI_Comm_size(node, &size);
  MPI_Comm_free(&node);
  return size;
}

void require_memory_per_rank(const par::Comm& comm, const MemoryEstimate& estimate) {
  const int sharing = ranks_on_node(comm);
  // MemAvailable differs between nodes: each rank checks its own, and one refusal stops all.
  par::run_collectively(
      comm, [&] { require_memory(with_baseline(estimate), node_memory_available(), sharing); });
}

std::string memory_summary(const par::Comm& comm, const MemoryEstimate& estimate) {
  const int sharing = ranks_on_node(comm);
  if (estimate.bytes == 0)
    return "memory: not estimated for this pipeline";
  std::string text = "memory: about " + format_bytes(with_baseline(estimate).per_rank(sharing)) +
                     " per rank at " + std::to_string(comm.size) + " ranks (" + estimate.key +
                     ": " + estimate.detail + ", plus about " + format_bytes(kBaselineBytes) +
                     " for the libraries)";
  if (const auto node = node_memory_available())
    text += "; " + format_bytes(node->bytes / std::uint64_t(sharing)) + " available per rank (" +
            node->source + " over " + std::to_string(sharing) + " ranks on this node)";
  return text;
}

void check_petsc_options(const par::Comm& comm) {
  par::run_collectively(comm, [&] {
    std::string message;
    PetscPushErrorHandler(record_first_message, &message);
    KSP ksp = nullptr;
    PetscErrorCode code = KSPCreate(comm.raw, &ksp);
    if (code == 0)
      code = KSPSetFromOptions(ksp);
    KSPDestroy(&ksp);
    PetscPopErrorHandler();
    if (code != 0) {
      const char* generic = nullptr;
      PetscErrorMessage(code, &generic, nullptr);
      TEXSIM_INPUT_ERROR("PETSc options: "
                         << (message.empty() ? (generic ? generic : "error") : message)
                         << " (check the -ksp_*/-pc_* options on the command "
                            "line and under petsc:)");
    }
  });
}

} // namespace texsim::app
