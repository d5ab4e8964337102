#include "vol/grid_checks.hpp"

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "core/memory_budget.hpp"

#include <limits>

namespace texsim::vol {

void require_grid_fits(const std::filesystem::path& path, std::int64_t nx, std::int64_t ny,
                       std::int64_t nz, std::uint64_t bytes_per_voxel) {
  constexpr std::int64_t kMaxEdge = std::numeric_limits<int>::max();
  const std::string shape =
      std::to_string(nx) + " x " + std::to_string(ny) + " x " + std::to_string(nz);
  if (nx <= 0 || ny <= 0 || nz <= 0 || nx > kMaxEdge || ny > kMaxEdge || nz > kMaxEdge)
    TEXSIM_INPUT_ERROR(shortened(path.string())
                       << ": volume of " << shape
                       << " voxels; expected dimensions in [1, 2^31 - 1] along every axis");
  const std::uint64_t bytes = saturating_multiply(
      saturating_multiply(saturating_multiply(std::uint64_t(nx), std::uint64_t(ny)),
                          std::uint64_t(nz)),
      bytes_per_voxel);
  const auto node = node_memory_available();
  if (bytes == UINT64_MAX || (node && bytes > node->bytes))
    TEXSIM_INPUT_ERROR(shortened(path.string())
                       << ": volume of " << shape << " voxels needs " << format_bytes(bytes)
                       << " in memory, more than the "
                       << (node ? format_bytes(node->bytes) + " available (" + node->source + ")"
                                : std::string("address space"))
                       << "; expected a smaller volume");
}

void refuse_non_finite_voxel(const std::filesystem::path& path, Dims dims, std::size_t index) {
  const std::size_t nx = std::size_t(dims.nx), ny = std::size_t(dims.ny);
  TEXSIM_INPUT_ERROR(shortened(path.string())
                     << ": voxel (" << index % nx << ", " << index / nx % ny << ", "
                     << index / (nx * ny) << ") is NaN or infinite; expected finite values");
}

} // namespace texsim::vol
