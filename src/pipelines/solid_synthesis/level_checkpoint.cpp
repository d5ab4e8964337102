#include "pipelines/solid_synthesis/level_checkpoint.hpp"

#include "core/error.hpp"
#include "pipelines/solid_synthesis/pyramid_synthesizer.hpp"

#include <span>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr const char* kDataset = "exemplar_coordinates";
/// Attribute: the fixed-point bits of the stored positions. Checkpoints of whole-voxel
/// coordinates (before sub-voxel positions) lack it.
constexpr const char* kSubvoxelAttribute = "subvoxel_bits";

std::uint64_t plane_size(int n) {
  return std::uint64_t(n) * std::uint64_t(n);
}

} // namespace

void save_level(const par::Comm& comm, const io::CheckpointStore& store, const CoordinateSlab& slab,
                const std::string& exemplar_hash) {
  static_assert(sizeof(Position) == 3 * sizeof(std::int32_t));
  const LevelLayout& layout = slab.layout();
  const int level = level_of(slab);
  auto writer = store.begin(level);
  // A replicated level is the same on every rank: rank 0 alone writes it.
  std::span<const Position> owned = slab.owned();
  if (layout.replicated && !comm.is_root())
    owned = {};
  const std::uint64_t offset = owned.empty() ? 0 : plane_size(layout.size) * layout.z_begin;
  writer.write<std::int32_t>(
      kDataset, {reinterpret_cast<const std::int32_t*>(owned.data()), owned.size() * 3}, offset,
      plane_size(layout.size) * layout.size, 3);
  writer.set_attribute("level", level);
  writer.set_attribute(kSubvoxelAttribute, kSubvoxelBits);
  writer.set_attribute("exemplar_hash", exemplar_hash);
  writer.commit();
}

CoordinateSlab load_level(const par::Comm& comm, const io::CheckpointReader& reader,
                          const std::string& exemplar_hash) {
  const std::string file = reader.path().string();
  if (!reader.has_dataset(kDataset) || !reader.has_attribute("level"))
    throw InputError(file + ": not a solid_synthesis checkpoint (no synthesized level)");
  if (reader.attribute_string("exemplar_hash") != exemplar_hash)
    throw InputError(file + ": written for different exemplar contents; the exemplar file "
                            "changed since, so restart without --restart");
  if (!reader.has_attribute(kSubvoxelAttribute) ||
      reader.attribute_int64(kSubvoxelAttribute) != kSubvoxelBits)
    throw InputError(file +
                     ": holds whole-voxel exemplar coordinates from an older texsim (this "
                     "one keeps positions to 1/" +
                     std::to_string(1 << kSubvoxelBits) + " voxel); restart without --restart");
  const auto level = static_cast<int>(reader.attribute_int64("level"));
  CoordinateSlab slab(level_layout(level, comm.rank, comm.size));
  const LevelLayout& layout = slab.layout();
  if (reader.global_count(kDataset) != plane_size(layout.size) * layout.size)
    throw InputError(file + ": level " + std::to_string(level) + " holds " +
                     std::to_string(reader.global_count(kDataset)) + " voxels instead of " +
                     std::to_string(plane_size(layout.size) * layout.size));
  auto owned = slab.owned();
  reader.read<std::int32_t>(kDataset,
                            {reinterpret_cast<std::int32_t*>(owned.data()), owned.size() * 3},
                            plane_size(layout.size) * layout.z_begin, owned.size());
  slab.exchange_halo(comm);
  return slab;
}

} // namespace texsim::pipelines::solid_synthesis
