#pragma once
/// Running the texsim binary from a test as a user would: a shell command line, started with a
/// clean environment so that an `mpirun` inside it is a fresh job even when the test program
/// itself runs under mpirun.
#include <filesystem>
#include <string>

namespace texsim::test {

/// What a finished command left behind.
struct CommandOutcome {
  int exit_code = -1; ///< the shell's exit code; -1 if it did not exit normally
  std::string output; ///< stdout and stderr together, in order
};

/// Runs `command` with /bin/sh in `working_dir`. The environment holds only PATH, HOME and
/// OMP_NUM_THREADS=1: no OMPI_* or PMIX_* variable of an enclosing MPI job reaches the command.
/// Not collective: call it on one process (rank 0 of an MPI test).
CommandOutcome
run_command(const std::string& command,
            const std::filesystem::path& working_dir = std::filesystem::current_path());

/// "<mpiexec> --allow-run-as-root --oversubscribe -n <ranks> <texsim binary>": the start of a
/// command line running texsim on `ranks` processes.
std::string texsim_under_mpirun(int ranks);

/// The texsim binary alone (a single process without mpirun).
std::string texsim_command();

} // namespace texsim::test
