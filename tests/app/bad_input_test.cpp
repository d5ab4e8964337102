// The bad-input corpus: every file in tests/app/bad_input/ is a config a user might write (with
// data files in bad_input/data/), run through the binary at 2 ranks as a user would. Each must
// end within a bounded time with exit code 2, exactly one "texsim: error" line containing the
// expected text, no MPI_Abort banner, and the earlier runs' directories untouched.
//
// A case file starts with comment lines that drive the runner:
//   # expect: TEXT            required: text the "texsim: error:" line contains
//   # args: validate CONFIG   command-line arguments (default: CONFIG, the case file's copy)
//   # env: NAME=VALUE         an environment variable for texsim (repeatable)
//   # fifo: NAME              a FIFO created in the working directory before the run
//   # ulimit: KIB             the address space of each process, in KiB (as ulimit -v; set with
//                             prlimit, a command, since the case's command line is exec'd)
//   # repeat: TOKEN N C       TOKEN in the case text and the arguments replaced by N copies of
//                             the character C
// Every case runs with TEXSIM_MEMORY_LIMIT=16G unless it sets its own, so memory refusals do not
// depend on the machine. The working directory holds a copy of data/, a finished fem_rd run in
// previous/ and an interrupted one (frames only) in interrupted/.
//
// A case spends most of its time asleep: after a rank exits non-zero, mpirun signals the job and
// waits odls_base_sigkill_timeout (1 s) before it ends, even when every rank has already exited.
// The cases run with that wait at 0 (a rank that hung would be killed at once instead of after a
// second, so only the timeout below still catches hangs, as before) and kConcurrentCases at a
// time (each test starts the cases after it and then waits for its own).
#include "support/run_command.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace {
namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(TEXSIM_SOURCE_DIR) / "tests/app/bad_input";
/// Generous: the slowest refusal takes a few seconds; only a hang reaches it.
constexpr int kTimeoutSeconds = 120;
/// Cases run at once: each uses little CPU (about 0.4 s of its 2.5 s).
constexpr std::size_t kConcurrentCases = 6;

struct BadInputCase {
  std::string name;
  std::string text;
  std::string expect;
  std::string args = "CONFIG";
  std::vector<std::string> env;
  std::vector<std::string> fifos;
  std::vector<std::string> repeats;
  std::string address_space_kib;
};

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

BadInputCase parse_case(const fs::path& path) {
  BadInputCase c;
  c.name = path.stem().string();
  c.text = read_text(path);
  std::istringstream lines(c.text);
  for (std::string line; std::getline(lines, line) && line.rfind("#", 0) == 0;) {
    const auto directive = [&](const std::string& name) -> std::optional<std::string> {
      const std::string prefix = "# " + name + ": ";
      if (line.rfind(prefix, 0) != 0)
        return std::nullopt;
      return line.substr(prefix.size());
    };
    if (auto v = directive("expect"))
      c.expect = *v;
    else if (auto v = directive("args"))
      c.args = *v;
    else if (auto v = directive("env"))
      c.env.push_back(*v);
    else if (auto v = directive("fifo"))
      c.fifos.push_back(*v);
    else if (auto v = directive("repeat"))
      c.repeats.push_back(*v);
    else if (auto v = directive("ulimit"))
      c.address_space_kib = *v;
  }
  return c;
}

std::vector<BadInputCase> all_cases() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(kCorpus))
    if (entry.path().extension() == ".yaml")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<BadInputCase> cases;
  for (const auto& file : files)
    cases.push_back(parse_case(file));
  return cases;
}

/// `text` with each "# repeat: TOKEN N C" of the case applied.
std::string expanded(const BadInputCase& c, std::string text) {
  for (const auto& repeat : c.repeats) {
    std::istringstream parts(repeat);
    std::string token;
    std::size_t count = 0;
    char fill = 'x';
    parts >> token >> count >> fill;
    for (auto pos = text.find(token); pos != std::string::npos; pos = text.find(token, pos + count))
      text.replace(pos, token.size(), std::string(count, fill));
  }
  return text;
}

void write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

/// What an earlier run left in a directory: each file's bytes and modification time.
using Snapshot = std::map<fs::path, std::pair<std::string, fs::file_time_type>>;

Snapshot snapshot(const fs::path& dir) {
  Snapshot files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file())
      files[entry.path()] = {read_text(entry.path()), entry.last_write_time()};
  return files;
}

/// A finished fem_rd run (summary, frames, a checkpoint) and an interrupted one (frames only).
void make_earlier_runs(const fs::path& work) {
  const std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n<Collection>\n"
                          "<DataSet timestep=\"0\" file=\"frames/frame_000000.pvtp\"/>\n"
                          "</Collection>\n</VTKFile>\n";
  for (const char* dir : {"previous", "interrupted"}) {
    write_file(work / dir / "fem_rd.pvd", pvd);
    write_file(work / dir / "frames/frame_000000.pvtp", "<VTKFile type=\"PPolyData\"/>\n");
  }
  write_file(work / "previous/summary.json", "{\"pipeline\": \"fem_rd\", \"ranks\": 2}\n");
  write_file(work / "previous/checkpoints/step_000000010.h5", "not really HDF5");
}

std::string shell_command(const BadInputCase& c, const fs::path& config) {
  std::vector<std::string> env = c.env;
  const bool has_limit = std::any_of(env.begin(), env.end(), [](const std::string& e) {
    return e.rfind("TEXSIM_MEMORY_LIMIT=", 0) == 0;
  });
  if (!has_limit)
    env.push_back("TEXSIM_MEMORY_LIMIT=16G");
  std::string command =
      c.address_space_kib.empty()
          ? "env"
          : "prlimit --as=" + std::to_string(std::stoull(c.address_space_kib) * 1024) + " env";
  std::string forwarded;
  for (const auto& assignment : env) {
    command += " " + assignment;
    forwarded += " -x " + assignment.substr(0, assignment.find('='));
  }
  std::string args = expanded(c, c.args);
  for (auto pos = args.find("CONFIG"); pos != std::string::npos; pos = args.find("CONFIG"))
    args.replace(pos, 6, config.string());
  const std::string mpirun =
      texsim::test::texsim_under_mpirun(2, "--mca odls_base_sigkill_timeout 0");
  const auto binary = mpirun.rfind(' ');
  return command + " timeout -k 10 " + std::to_string(kTimeoutSeconds) + " " +
         mpirun.substr(0, binary) + forwarded + mpirun.substr(binary) + " " + args;
}

/// A case started in the background: its working directory, the earlier runs' contents before
/// it started, and the command (or why it could not be started).
struct StartedCase {
  fs::path work;
  Snapshot before_previous;
  Snapshot before_interrupted;
  std::unique_ptr<texsim::test::BackgroundCommand> command;
  std::string setup_error;
};

StartedCase start_case(const BadInputCase& c) {
  StartedCase started;
  started.work = fs::temp_directory_path() / "texsim_bad_input" / c.name;
  const fs::path& work = started.work;
  fs::remove_all(work);
  fs::create_directories(work);
  fs::copy(kCorpus / "data", work / "data", fs::copy_options::recursive);
  make_earlier_runs(work);
  for (const auto& fifo : c.fifos)
    if (mkfifo((work / fifo).c_str(), 0600) != 0)
      started.setup_error = "mkfifo " + fifo + " failed";
  const fs::path config = work / (c.name + ".yaml");
  write_file(config, expanded(c, c.text));
  started.before_previous = snapshot(work / "previous");
  started.before_interrupted = snapshot(work / "interrupted");
  if (started.setup_error.empty())
    started.command =
        std::make_unique<texsim::test::BackgroundCommand>(shell_command(c, config), work);
  return started;
}

/// Every case of the corpus, started kConcurrentCases ahead of the one a test waits for.
class CorpusRunner {
public:
  /// Starts case `index` and the cases after it, up to kConcurrentCases running.
  StartedCase& started(std::size_t index) {
    const std::vector<BadInputCase>& cases = corpus();
    for (std::size_t i = index; i < std::min(cases.size(), index + kConcurrentCases); ++i)
      if (!started_.contains(i))
        started_.emplace(i, start_case(cases[i]));
    return started_.at(index);
  }
  void forget(std::size_t index) { started_.erase(index); }

  static const std::vector<BadInputCase>& corpus() {
    static const std::vector<BadInputCase> cases = all_cases();
    return cases;
  }

private:
  std::map<std::size_t, StartedCase> started_;
};

CorpusRunner& runner() {
  static CorpusRunner instance;
  return instance;
}

class BadInput : public testing::TestWithParam<std::size_t> {};

TEST_P(BadInput, ExitsTwoWithOneMessageAndTouchesNothing) {
  const BadInputCase& c = CorpusRunner::corpus()[GetParam()];
  ASSERT_FALSE(c.expect.empty()) << c.name << ": no '# expect:' line";
  StartedCase& started = runner().started(GetParam());
  ASSERT_TRUE(started.setup_error.empty()) << started.setup_error;
  const auto outcome = started.command->finish();

  EXPECT_NE(outcome.exit_code, 124) << "timed out after " << kTimeoutSeconds << " s (a hang)";
  EXPECT_EQ(outcome.exit_code, 2) << outcome.output;
  std::vector<std::string> error_lines;
  std::istringstream lines(outcome.output);
  for (std::string line; std::getline(lines, line);)
    if (line.find("texsim: error") != std::string::npos)
      error_lines.push_back(line);
  ASSERT_EQ(error_lines.size(), 1u) << outcome.output;
  EXPECT_NE(error_lines[0].find(c.expect), std::string::npos)
      << "expected '" << c.expect << "' in\n"
      << error_lines[0];
  std::string lower = outcome.output;
  std::transform(lower.begin(), lower.end(), lower.begin(), ::tolower);
  EXPECT_EQ(lower.find("mpi_abort"), std::string::npos) << outcome.output;
  EXPECT_LT(error_lines[0].size(), 2000u) << "an echoed name was not shortened";
  EXPECT_EQ(snapshot(started.work / "previous"), started.before_previous) << "previous/ changed";
  EXPECT_EQ(snapshot(started.work / "interrupted"), started.before_interrupted)
      << "interrupted/ changed";
  fs::remove_all(started.work);
  runner().forget(GetParam());
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInput,
                         testing::Range(std::size_t{0}, CorpusRunner::corpus().size()),
                         [](const testing::TestParamInfo<std::size_t>& info) {
                           std::string name = CorpusRunner::corpus()[info.param].name;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch)))
                               ch = '_';
                           return name;
                         });

TEST(BadInputCorpus, HoldsAtLeastAHundredCases) {
  EXPECT_GE(all_cases().size(), 100u);
}

} // namespace
