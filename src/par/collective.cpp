#include "par/collective.hpp"

#include "core/error.hpp"
#include "core/memory_budget.hpp"

#include <filesystem>
#include <new>
#include <string>

namespace texsim::par {
namespace {
enum FailureKind : int { kNone = 0, kError = 1, kInput = 2 };
}

void run_collectively(const Comm& comm, const std::function<void()>& work) {
  int kind = kNone;
  std::string message;
  try {
    work();
  } catch (const InputError& e) {
    kind = kInput;
    message = e.what();
  } catch (const std::bad_alloc&) {
    // Memory is an input limit: the config asked for more than the node has.
    kind = kInput;
    message = out_of_memory_message(comm.rank);
  } catch (const std::filesystem::filesystem_error& e) {
    // A path from the config that the file system refuses (too long, not permitted, ...).
    kind = kInput;
    message = e.what();
  } catch (const std::exception& e) {
    kind = kError;
    message = e.what();
  }
  int worst = kNone;
  MPI_Allreduce(&kind, &worst, 1, MPI_INT, MPI_MAX, comm.raw);
  if (worst == kNone)
    return;
  // The lowest rank whose failure is of the worst kind speaks for all.
  int candidate = kind == worst ? comm.rank : comm.size;
  int speaker = comm.size;
  MPI_Allreduce(&candidate, &speaker, 1, MPI_INT, MPI_MIN, comm.raw);
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, speaker, comm.raw);
  message.resize(length);
  MPI_Bcast(message.data(), length, MPI_CHAR, speaker, comm.raw);
  if (worst == kInput) {
    InputError error(message);
    error.mark_on_all_ranks();
    throw error;
  }
  Error error(message);
  error.mark_on_all_ranks();
  throw error;
}

} // namespace texsim::par
