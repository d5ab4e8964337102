#include "app/command_line.hpp"

#include "core/config.hpp"
#include "core/error.hpp"
#include "core/input_file.hpp"

#include <array>
#include <utility>

namespace texsim::app {
namespace {
constexpr std::array<const char*, 6> kOptions = {"--set",  "--restart", "--quiet",
                                                 "--help", "--version", "--set=KEY=VALUE"};

bool is_checkpoint_argument(const std::string& text) {
  return text == "latest" || (text.size() > 3 && text.compare(text.size() - 3, 3, ".h5") == 0);
}

/// PETSc reads -options_file FILE while it starts, before texsim can report anything: a missing
/// file would abort every rank, a FIFO or /dev/zero would hang them.
void check_options_file(const std::string& option, const std::string& file) {
  constexpr std::uint64_t kMaxOptionsFileBytes = 1 << 20;
  if (file.empty())
    throw InputError(option + " needs a file name");
  require_regular_file(file, "PETSc options file for " + option, kMaxOptionsFileBytes);
}

[[noreturn]] void unknown_option(const std::string& option) {
  std::string hint;
  for (const char* known : kOptions)
    if (edit_distance(option, known) <= 2)
      hint = std::string(" (did you mean ") + known + "?)";
  throw InputError("unknown option " + shortened(option) + hint + "; see texsim --help");
}
} // namespace

std::string usage_text() {
  return R"(texsim: texture synthesis on surfaces, in volumes and on fluids

usage:
  texsim CONFIG.yaml [--set key.path=value ...] [--restart [CHECKPOINT]] [--quiet] [PETSc options]
  texsim validate CONFIG.yaml [CONFIG.yaml ...] [--set key.path=value ...]
  texsim --help | --version

  CONFIG.yaml        the run's configuration; `pipeline:` selects the method
  --set K=V          override one config key (same validation as the file), repeatable
  --restart [CKPT]   continue from a checkpoint: a .h5 path, or the latest good one in
                     output.dir/checkpoints when CKPT is omitted or "latest"
  --quiet            no progress lines (warnings and errors still print)
  -ksp_type cg ...   any option with one dash goes to PETSc (the config's `petsc:` map too;
                     the command line wins)

Run in parallel with:  mpirun -n 64 texsim CONFIG.yaml
Exit codes: 0 success, 2 bad input (config, files, checkpoints), 1 internal failure.
)";
}

CommandLine parse_command_line(int argc, const char* const* argv) {
  CommandLine line;
  line.petsc_args.push_back(argc > 0 ? argv[0] : "texsim");
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_next = i + 1 < argc;
    if (arg == "--help" || arg == "-h") {
      line.command = Command::kHelp;
    } else if (arg == "--version") {
      line.command = Command::kVersion;
    } else if (arg == "--quiet") {
      line.quiet = true;
    } else if (arg == "--set") {
      if (!has_next)
        throw InputError("--set needs key.path=value");
      line.overrides.push_back(argv[++i]);
    } else if (arg.rfind("--set=", 0) == 0) {
      line.overrides.push_back(arg.substr(6));
    } else if (arg == "--restart") {
      line.restart = "latest";
      if (has_next && is_checkpoint_argument(argv[i + 1]))
        line.restart = argv[++i];
    } else if (arg.rfind("--restart=", 0) == 0) {
      line.restart = arg.substr(10);
      if (line.restart->empty())
        throw InputError("--restart= needs a checkpoint path after '='; use --restart alone for "
                         "the latest checkpoint in output.dir/checkpoints");
    } else if (arg.rfind("--", 0) == 0) {
      unknown_option(arg);
    } else if (arg.size() > 1 && arg[0] == '-') {
      line.petsc_args.push_back(arg);
      if (has_next && argv[i + 1][0] != '-')
        line.petsc_args.push_back(argv[++i]);
      if (arg.rfind("-options_file", 0) == 0)
        check_options_file(arg, line.petsc_args.back() == arg ? "" : line.petsc_args.back());
    } else {
      positional.push_back(arg);
    }
  }
  if (line.command == Command::kHelp || line.command == Command::kVersion)
    return line;
  if (!positional.empty() && positional.front() == "validate") {
    line.command = Command::kValidate;
    positional.erase(positional.begin());
  }
  if (positional.empty())
    throw InputError("no config file given; usage: texsim CONFIG.yaml (see texsim --help)");
  if (positional.size() > 1 && line.command != Command::kValidate)
    throw InputError("expected one config file, got '" + shortened(positional[0]) + "' and '" +
                     shortened(positional[1]) +
                     "' (see texsim --help; `texsim validate` takes several)");
  line.config_paths = std::move(positional);
  return line;
}

} // namespace texsim::app
