#include "core/memory_budget.hpp"

#include "core/error.hpp"

#include <charconv>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace texsim {
namespace {

std::optional<NodeMemory> limit_from_environment() {
  const char* text = std::getenv("TEXSIM_MEMORY_LIMIT");
  if (text == nullptr || *text == '\0')
    return std::nullopt;
  const std::string value = text;
  std::uint64_t number = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
  const std::string suffix(end, value.data() + value.size());
  std::uint64_t unit = 0;
  if (suffix.empty())
    unit = 1;
  else if (suffix == "K")
    unit = 1ull << 10;
  else if (suffix == "M")
    unit = 1ull << 20;
  else if (suffix == "G")
    unit = 1ull << 30;
  else if (suffix == "T")
    unit = 1ull << 40;
  if (error != std::errc() || unit == 0 || number == 0)
    TEXSIM_INPUT_ERROR("TEXSIM_MEMORY_LIMIT=" << value
                                              << ": expected a positive number of bytes, with an "
                                                 "optional suffix K, M, G or T (e.g. 8G)");
  return NodeMemory{saturating_multiply(number, unit), "TEXSIM_MEMORY_LIMIT"};
}

std::optional<NodeMemory> limit_from_meminfo() {
  std::ifstream meminfo("/proc/meminfo");
  std::string name;
  std::uint64_t kib = 0;
  std::string unit;
  while (meminfo >> name >> kib >> unit)
    if (name == "MemAvailable:")
      return NodeMemory{saturating_multiply(kib, 1024), "MemAvailable"};
  return std::nullopt;
}

} // namespace

MemoryEstimate larger(const MemoryEstimate& a, const MemoryEstimate& b) {
  return b.bytes > a.bytes ? b : a;
}

std::optional<NodeMemory> node_memory_available() {
  if (auto limit = limit_from_environment())
    return limit;
  return limit_from_meminfo();
}

std::string format_bytes(std::uint64_t bytes) {
  static constexpr const char* kUnits[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  if (bytes == UINT64_MAX)
    return "more than 16 EiB";
  double value = static_cast<double>(bytes);
  int unit = 0;
  while (value >= 1024.0 && unit < 6) {
    value /= 1024.0;
    ++unit;
  }
  std::ostringstream out;
  if (unit == 0)
    out << bytes << " bytes";
  else
    out << std::setprecision(value < 10 ? 2 : 3) << value << " " << kUnits[unit];
  return out.str();
}

std::string out_of_memory_message(int rank) {
  return "out of memory on rank " + std::to_string(rank) +
         " (std::bad_alloc): the config asks for more memory than this node has; `texsim "
         "validate` prints the estimate; lower the sizes or run on more nodes";
}

void require_memory(const MemoryEstimate& estimate, const std::optional<NodeMemory>& node,
                    int ranks_on_node) {
  if (estimate.bytes == 0 || !node || ranks_on_node <= 0)
    return;
  const std::uint64_t per_rank = node->bytes / static_cast<std::uint64_t>(ranks_on_node);
  const std::uint64_t needed = estimate.per_rank(ranks_on_node);
  if (needed <= per_rank)
    return;
  TEXSIM_INPUT_ERROR(estimate.key << ": the run needs about " << format_bytes(needed)
                                  << " per rank (" << estimate.detail << "), but "
                                  << format_bytes(per_rank) << " is available per rank ("
                                  << node->source << " " << format_bytes(node->bytes) << " over "
                                  << ranks_on_node
                                  << " ranks on this node); choose a smaller value, or run on more "
                                     "nodes if the work is divided among ranks");
}

} // namespace texsim
