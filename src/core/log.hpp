#pragma once
/// Logging: only rank 0 prints; --quiet silences info lines (warnings and errors still print).
#include <sstream>
#include <string>

namespace texsim::log {

/// Called once by main() after MPI is up.
void init(int rank, bool quiet);

/// True on the rank that prints info lines (rank 0 without --quiet).
bool info_enabled();

/// One line on stdout, rank 0 only.
void info(const std::string& line);

/// `line` and a newline on stderr in one write: mpirun forwards stdout and stderr separately, and a
/// line written in pieces can be cut by another rank's output (the bad-input corpus saw the banner
/// land inside "texsim: error: ..."). Any rank.
void error_line(const std::string& line);

/// One line on stderr prefixed "warning: ", rank 0 only, even with --quiet.
void warn(const std::string& line);

/// Concatenates anything streamable: log::info(log::cat("step ", n, " of ", total));
template <class... Parts> std::string cat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

} // namespace texsim::log
