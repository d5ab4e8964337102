#include "pipelines/solid_synthesis/memory_estimate.hpp"

#include <algorithm>
#include <filesystem>
#include <string>
#include <system_error>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Bytes per exemplar voxel that the busiest rank holds: rank 0 loads the exemplar (the file's
/// grid and its colours, before they move to the node windows) and builds the finest level's
/// kd-tree (lane blocks, boxes, leaf voxels, the build's order: about 5 bytes a channel and
/// 9 bytes) before it moves to the node windows; any rank, a share of a level being blurred or
/// projected.
std::uint64_t rank_bytes_per_voxel(const SolidSynthesisSettings& settings) {
  return std::max<std::uint64_t>(24, 5 * std::uint64_t(settings.appearance.dimensions) + 9);
}

/// Bytes per exemplar voxel of the finest level held once per node while its similarity sets
/// are built: the kd-tree (as above, without the build's order), the feature twins and the
/// queries' order (the tree's leaves without padding).
std::uint64_t search_bytes_per_voxel(const SolidSynthesisSettings& settings) {
  return 5 * std::uint64_t(settings.appearance.dimensions) + 5 + 12 + 4;
}

/// Bytes per exemplar voxel and stack level held once per node (par::NodeSharedArray): the
/// stack's colours, `dimensions` float features, k similarity candidates, and room for the copies
/// made while they are built and for the correction's candidate coordinates.
std::uint64_t node_bytes_per_voxel(const SolidSynthesisSettings& settings) {
  return 12 + 8 * std::uint64_t(settings.appearance.dimensions) +
         8 * std::uint64_t(settings.similarity.k);
}

MemoryEstimate exemplar_estimate(const SolidSynthesisSettings& settings) {
  const auto& exemplar = settings.exemplar;
  std::uint64_t voxels = 0;
  std::string key;
  std::string shape;
  if (exemplar.file) {
    std::error_code error;
    voxels = std::filesystem::file_size(*exemplar.file, error) / 4;
    key = exemplar.key_path + ".file";
    shape = "about " + std::to_string(voxels) + " voxels (from the file size)";
  } else {
    const auto edge = std::uint64_t(exemplar.size);
    voxels = edge * edge * edge;
    key = exemplar.key_path + ".size";
    shape = std::to_string(edge) + "^3 voxels";
  }
  int octaves = 1;
  while ((std::uint64_t(1) << octaves) * (std::uint64_t(1) << octaves) *
             (std::uint64_t(1) << octaves) <
         voxels)
    ++octaves;
  const std::uint64_t level_voxels = saturating_multiply(voxels, std::uint64_t(octaves + 1));
  return {saturating_multiply(voxels, rank_bytes_per_voxel(settings)), key,
          "exemplar of " + shape + " x " + std::to_string(octaves + 1) +
              " stack levels, its features, similarity sets and search tree held once per node",
          saturating_add(saturating_multiply(level_voxels, node_bytes_per_voxel(settings)),
                         saturating_multiply(voxels, search_bytes_per_voxel(settings)))};
}

MemoryEstimate synthesis_estimate(const SolidSynthesisSettings& settings, int ranks) {
  const auto& dims = settings.dims;
  const std::uint64_t edge = std::uint64_t(*std::max_element(dims.begin(), dims.end()));
  std::uint64_t pyramid_edge = 1;
  while (pyramid_edge < edge)
    pyramid_edge *= 2;
  const std::uint64_t pyramid_voxels =
      saturating_multiply(saturating_multiply(pyramid_edge, pyramid_edge), pyramid_edge);
  const std::uint64_t result_voxels =
      std::uint64_t(dims[0]) * std::uint64_t(dims[1]) * std::uint64_t(dims[2]);
  // Per pyramid voxel: coordinates, features and the next level's copy (all levels: x 8/7).
  const std::uint64_t distributed = saturating_multiply(pyramid_voxels, 64) / std::uint64_t(ranks);
  // Each rank's coloured planes (12 bytes a colour voxel; the exemplar features are freed by
  // then), the 7 more that finish its last .vdb leaf layer and the leaf records of 32 planes.
  const std::uint64_t output = saturating_add(
      saturating_multiply(result_voxels, 12) / std::uint64_t(ranks),
      saturating_multiply(std::uint64_t(dims[0]) * std::uint64_t(dims[1]), (7 + 32) * 12));
  const bool cube = dims[0] == dims[1] && dims[1] == dims[2];
  const std::string key =
      std::string("solid_synthesis.synthesis.") + (cube ? "size (or dims)" : "dims");
  return {saturating_add(distributed, output), key,
          std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
              std::to_string(dims[2]) + " voxels, a " + std::to_string(pyramid_edge) +
              "^3 pyramid divided among " + std::to_string(ranks) + " ranks"};
}

} // namespace

MemoryEstimate estimate_solid_synthesis_memory(const SolidSynthesisSettings& settings, int ranks) {
  const MemoryEstimate exemplar = exemplar_estimate(settings);
  MemoryEstimate synthesis = synthesis_estimate(settings, ranks);
  if (settings.mode == RunMode::similarity_sets)
    return exemplar;
  // The key of the larger term for one rank on a node.
  MemoryEstimate total = exemplar.per_rank(1) > synthesis.bytes ? exemplar : synthesis;
  total.bytes = saturating_add(exemplar.bytes, synthesis.bytes);
  total.node_shared_bytes = exemplar.node_shared_bytes;
  return total;
}

} // namespace texsim::pipelines::solid_synthesis
