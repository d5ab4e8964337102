#include "core/log.hpp"

#include <cstdio>
#include <iostream>

namespace texsim::log {
namespace {
int g_rank = 0;
bool g_quiet = false;
} // namespace

void init(int rank, bool quiet) {
  g_rank = rank;
  g_quiet = quiet;
}

bool info_enabled() {
  return g_rank == 0 && !g_quiet;
}

void info(const std::string& line) {
  if (info_enabled())
    std::cout << line << std::endl;
}

void error_line(const std::string& line) {
  const std::string whole = line + "\n";
  std::fwrite(whole.data(), 1, whole.size(), stderr);
  std::fflush(stderr);
}

void warn(const std::string& line) {
  if (g_rank == 0)
    error_line("warning: " + line);
}

} // namespace texsim::log
