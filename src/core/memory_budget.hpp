#pragma once
/// Refusing a run whose memory per rank would exceed the machine's before anything is allocated.
///
/// A pipeline estimates the peak bytes per rank from its config (MemoryEstimate, naming the key
/// that drives it); main() compares it with the memory available to each rank of the node and
/// refuses the run with exit code 2. `texsim validate` prints the estimate.
#include <cstdint>
#include <optional>
#include <string>

namespace texsim {

/// a * b, or UINT64_MAX when the product does not fit: sizes computed from user input saturate
/// instead of wrapping around to a small number.
constexpr std::uint64_t saturating_multiply(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > UINT64_MAX / a)
    return UINT64_MAX;
  return a * b;
}

/// a + b, or UINT64_MAX when the sum does not fit.
constexpr std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
  return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}

/// Peak bytes per rank of a run, and the config key path that contributes most to it.
struct MemoryEstimate {
  std::uint64_t bytes = 0; ///< peak bytes per rank (besides node_shared_bytes); 0: not estimated
  std::string key;         ///< e.g. "solid_synthesis.synthesis.size"
  std::string detail;      ///< what the estimate counts, e.g. "512^3 voxels x 3 levels"
  /// Bytes held once per node whatever its rank count (par::NodeSharedArray), shared by its ranks.
  std::uint64_t node_shared_bytes = 0;

  /// What one of `ranks_on_node` ranks needs: its own bytes and its share of the node's.
  std::uint64_t per_rank(int ranks_on_node) const {
    const auto ranks = static_cast<std::uint64_t>(ranks_on_node > 0 ? ranks_on_node : 1);
    return saturating_add(bytes, saturating_add(node_shared_bytes, ranks - 1) / ranks);
  }
};

/// The estimate with the larger byte count.
MemoryEstimate larger(const MemoryEstimate& a, const MemoryEstimate& b);

/// Memory the node offers to all its ranks together, and where the figure comes from.
struct NodeMemory {
  std::uint64_t bytes = 0;
  std::string source; ///< "MemAvailable" or "TEXSIM_MEMORY_LIMIT"
};

/// The TEXSIM_MEMORY_LIMIT environment variable when set (bytes, or a number with suffix K, M, G
/// or T, powers of 1024; tests set it to be independent of the machine), otherwise MemAvailable
/// from /proc/meminfo; nullopt when neither is known. Throws InputError for a malformed
/// TEXSIM_MEMORY_LIMIT. Serial.
std::optional<NodeMemory> node_memory_available();

/// "1.5 GiB", "812 MiB", "64 KiB", "12 bytes".
std::string format_bytes(std::uint64_t bytes);

/// Throws InputError "<key>: the run needs about <estimate> per rank (<detail>), but <available>
/// is available per rank (<source> <bytes> over <ranks_on_node> ranks on this node); ..." when the
/// estimate (per_rank(ranks_on_node)) exceeds the node's memory divided among its ranks. Does
/// nothing when the estimate or the node's memory is unknown. Serial: every rank given the same
/// values decides the same.
void require_memory(const MemoryEstimate& estimate, const std::optional<NodeMemory>& node,
                    int ranks_on_node);

/// The message for a std::bad_alloc on `rank`: memory is an input limit (exit code 2).
std::string out_of_memory_message(int rank);

} // namespace texsim
