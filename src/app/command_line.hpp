#pragma once
/// Parsing texsim's command line. texsim's own options use two dashes; anything with one dash is a
/// PETSc option (-ksp_type cg) and is passed on to PETSc with its value.
#include <optional>
#include <string>
#include <vector>

namespace texsim::app {

enum class Command { kRun, kValidate, kHelp, kVersion };

struct CommandLine {
  Command command = Command::kRun;
  std::vector<std::string> config_paths; ///< exactly one, or several for `validate`
  std::vector<std::string> overrides;    ///< --set key.path=value, in order
  std::optional<std::string> restart;    ///< --restart: "latest" unless a checkpoint path follows
  bool quiet = false;
  std::vector<std::string> petsc_args; ///< argv[0] followed by the PETSc options
};

/// Throws InputError with a usage hint on unknown options or a missing config path.
CommandLine parse_command_line(int argc, const char* const* argv);

/// The text `texsim --help` prints.
std::string usage_text();

} // namespace texsim::app
