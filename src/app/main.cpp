// texsim: one binary for every pipeline. MPI and PETSc are initialised once here; the config is
// read and validated on rank 0, broadcast, and every rank builds the same typed settings from it.
#include "app/command_line.hpp"
#include "app/error_report.hpp"
#include "app/output_dir.hpp"
#include "app/pipeline_registry.hpp"
#include "app/preflight.hpp"
#include "app/run_settings.hpp"
#include "app/summary_writer.hpp"
#include "core/float_distance_scan.hpp"
#include "core/log.hpp"
#include "core/peak_memory.hpp"
#include "core/stage_timers.hpp"
#include "core/stop_signal.hpp"
#include "par/collective.hpp"
#include "par/petsc_session.hpp"
#include "texsim/version.hpp"

#include <H5public.h>
#include <omp.h>

#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace texsim::app {
namespace {

/// Where this executable runs from: an install prefix (the directory above its bin/), or the
/// build tree.
std::string install_location() {
  std::error_code error;
  const auto executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error)
    return "location unknown";
  const auto directory = executable.parent_path();
  if (directory.filename() == "bin")
    return "prefix: " + directory.parent_path().string();
  return "build tree: " + directory.string();
}

void print_version() {
  unsigned major = 0, minor = 0, release = 0;
  H5get_libversion(&major, &minor, &release);
  std::cout << "texsim " << build_info::kVersion << " (git " << build_info::kGitHash << ")\n"
            << "  PETSc " << build_info::kPetscVersion << ", HDF5 " << major << "." << minor << "."
            << release << ", VTK " << build_info::kVtkVersion << ", OpenVDB "
            << build_info::kOpenVdbVersion << "\n"
            << "  pipelines: " << registered_pipeline_list() << "\n"
            << "  " << install_location() << "\n";
}

/// The config after --set overrides, validated on rank 0 and broadcast as YAML text.
std::string read_config_on_root(const par::Comm& comm, const CommandLine& line,
                                const std::string& config_path) {
  std::string text;
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    auto document = ConfigDocument::load(config_path);
    for (const auto& assignment : line.overrides)
      document.set_override(assignment);
    text = document.emit();
  });
  int length = static_cast<int>(text.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm.raw);
  text.resize(length);
  MPI_Bcast(text.data(), length, MPI_CHAR, 0, comm.raw);
  return text;
}

struct ConfiguredRun {
  CommonConfig common;
  std::unique_ptr<pipelines::Pipeline> pipeline;
};

/// Builds the typed settings from the broadcast text on every rank; unknown keys are errors.
ConfiguredRun configure(const par::Comm& comm, const std::string& text, const CommandLine& line,
                        const std::string& config_path) {
  ConfiguredRun run;
  par::run_collectively(comm, [&] {
    auto document = ConfigDocument::parse(text, config_path);
    auto root = document.root();
    run.common = read_common_config(root);
    run.common.run.restart = line.restart;
    run.pipeline = make_pipeline(run.common.pipeline);
    run.common.run.config_hash = document.result_hash(run.pipeline->run_length_keys());
    run.pipeline->configure(root.section(run.common.pipeline), run.common.run);
    document.check_unknown_keys();
    best_scan_isa(); // TEXSIM_SCAN_ISA is checked here, not first inside a threaded search
  });
  return run;
}

/// PETSc options from the config's `petsc:` map; the command line, already inserted, wins.
void insert_petsc_options(const std::map<std::string, std::string>& options) {
  for (const auto& [name, value] : options) {
    const std::string option = "-" + name;
    PetscBool already = PETSC_FALSE;
    TEXSIM_PETSC_CALL(PetscOptionsHasName(nullptr, nullptr, option.c_str(), &already));
    if (!already)
      TEXSIM_PETSC_CALL(
          PetscOptionsSetValue(nullptr, option.c_str(), value.empty() ? nullptr : value.c_str()));
  }
}

/// `texsim validate`: each config read, configured and its memory estimated, as a run would,
/// without the work. With several configs, an error names the file it comes from.
void validate(const par::Comm& comm, const CommandLine& line) {
  for (const std::string& config_path : line.config_paths) {
    try {
      const std::string text = read_config_on_root(comm, line, config_path);
      ConfiguredRun run = configure(comm, text, line, config_path);
      MemoryEstimate memory;
      par::run_collectively(comm, [&] { memory = run.pipeline->estimate_memory(comm.size); });
      log::info(log::cat(config_path, ": valid ", run.common.pipeline, " config (config hash ",
                         run.common.run.config_hash, ")\n", memory_summary(comm, memory), "\n---\n",
                         text));
    } catch (const InputError& error) {
      if (line.config_paths.size() == 1)
        throw;
      InputError named(config_path + ": " + error.what());
      if (error.on_all_ranks())
        named.mark_on_all_ranks();
      throw named;
    }
  }
}

int execute(const par::Comm& comm, const CommandLine& line) {
  const double start_s = wall_seconds();
  const std::string& config_path = line.config_paths.front();
  const std::string text = read_config_on_root(comm, line, config_path);
  ConfiguredRun run = configure(comm, text, line, config_path);
  MemoryEstimate memory;
  par::run_collectively(comm, [&] { memory = run.pipeline->estimate_memory(comm.size); });
  require_memory_per_rank(comm, memory);
  insert_petsc_options(run.common.petsc);
  check_petsc_options(comm);
  prepare_output_dir(comm, run.common, *run.pipeline);

  log::info(log::cat("texsim ", build_info::kVersion, ": pipeline ", run.common.pipeline, " on ",
                     comm.size, " ranks x ", omp_get_max_threads(), " threads, output in ",
                     run.common.run.output_dir.string()));
  StageTimers timers;
  RunReport report;
  pipelines::RunContext context{comm, run.common.run, timers, report};
  run.pipeline->run(context);

  const std::int64_t peak = peak_resident_bytes();
  std::vector<std::int64_t> peaks(comm.is_root() ? static_cast<std::size_t>(comm.size) : 0);
  MPI_Gather(&peak, 1, MPI_INT64_T, peaks.data(), 1, MPI_INT64_T, 0, comm.raw);
  const std::int64_t proportional =
      std::max(timers.largest_proportional_bytes(), proportional_resident_bytes());
  std::vector<std::int64_t> proportionals(peaks.size());
  MPI_Gather(&proportional, 1, MPI_INT64_T, proportionals.data(), 1, MPI_INT64_T, 0, comm.raw);
  if (comm.is_root()) {
    SummaryHeader header{run.common.pipeline,        comm.size,
                         omp_get_max_threads(),      wall_seconds() - start_s,
                         run.common.run.config_hash, run.common.run.restart.has_value(),
                         std::move(peaks),           std::move(proportionals)};
    write_summary(run.common.run.output_dir, header, timers, report);
  }
  log::info(log::cat("done in ", wall_seconds() - start_s,
                     " s; summary: ", (run.common.run.output_dir / "summary.json").string()));
  for (const auto& output : report.outputs())
    if (std::filesystem::path(output).extension() == ".pvd")
      log::info("open in ParaView: paraview " + output);
  return 0;
}

} // namespace
} // namespace texsim::app

int main(int argc, char** argv) {
  using namespace texsim;
  app::CommandLine line;
  std::string usage_error;
  try {
    line = app::parse_command_line(argc, argv);
  } catch (const InputError& e) {
    usage_error = e.what();
  }
  // PETSc sees only the PETSc options, never texsim's own.
  std::vector<char*> petsc_argv;
  for (auto& arg : line.petsc_args)
    petsc_argv.push_back(arg.data());
  if (petsc_argv.empty())
    petsc_argv.push_back(argv[0]);
  int petsc_argc = static_cast<int>(petsc_argv.size());
  petsc_argv.push_back(nullptr);
  char** petsc_argv_data = petsc_argv.data();

  int exit_code = 0;
  {
    par::PetscSession session(petsc_argc, petsc_argv_data);
    const par::Comm comm = par::world();
    const app::ErrorReport error_report(comm);
    log::init(comm.rank, line.quiet);
    // After PETSc's initialisation, which installs handlers of its own.
    install_stop_signal_handlers();
    try {
      if (!usage_error.empty())
        throw InputError(usage_error);
      if (line.command == app::Command::kHelp) {
        if (comm.is_root())
          std::cout << app::usage_text();
      } else if (line.command == app::Command::kVersion) {
        if (comm.is_root())
          app::print_version();
      } else if (line.command == app::Command::kValidate) {
        app::validate(comm, line);
      } else {
        exit_code = app::execute(comm, line);
      }
    } catch (const CheckpointedStop& stop) {
      // Thrown on every rank after the checkpoint was written collectively.
      exit_code = kExitCheckpointed;
      if (comm.is_root())
        std::cerr << "texsim: stopped: " << stop.what() << std::endl;
    } catch (...) {
      exit_code = error_report.finish(std::current_exception());
    }
  }
  // PetscFinalize restores the signal handlers it found at start-up (the default: die). A stop
  // signal that arrives now, after the work is done, must not turn a finished run into a killed
  // one.
  install_stop_signal_handlers();
  return exit_code;
}
