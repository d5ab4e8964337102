#include "pipelines/surface_synthesis/synthesis_checkpoint.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/log.hpp"

namespace texsim::pipelines::surface_synthesis {
namespace {

std::string level_name(std::size_t level, const char* what) {
  return "level" + std::to_string(level) + "_" + what;
}

} // namespace

std::string hierarchy_hash(const std::vector<RetiledLevel>& pyramid) {
  std::uint64_t state = kFnv1a64Offset;
  for (const auto& level : pyramid)
    state =
        fnv1a64({reinterpret_cast<const char*>(&level.mesh_hash), sizeof level.mesh_hash}, state);
  return hex64(state);
}

void save_synthesis(const par::Comm& comm, const io::CheckpointStore& store, std::int64_t step,
                    const std::vector<RetiledLevel>& pyramid,
                    const std::vector<LevelColours>& colours, const SynthesisPosition& position,
                    const SynthesisIdentity& identity) {
  auto writer = store.begin(step);
  const int rank = comm.rank;
  for (std::size_t k = 0; k < pyramid.size(); ++k) {
    const auto& offsets = pyramid[k].rank_offsets;
    const auto first = std::size_t(offsets[std::size_t(rank)]);
    const auto count = std::size_t(offsets[std::size_t(rank) + 1]) - first;
    const auto total = std::uint64_t(offsets.back());
    TEXSIM_VERIFY(colours[k].colours.size() == count && colours[k].pixels.size() == count,
                  "level " << k << ": " << colours[k].colours.size() << " colours for a run of "
                           << count);
    const std::span<const float> rgb(reinterpret_cast<const float*>(colours[k].colours.data()),
                                     3 * count);
    writer.write<float>(level_name(k, "colour"), rgb, first, total, 3);
    writer.write<std::int32_t>(level_name(k, "pixel"), std::span(colours[k].pixels), first, total);
  }
  writer.set_attribute("level", std::int64_t(position.level));
  writer.set_attribute("pass", std::int64_t(position.pass));
  writer.set_attribute("next_class", std::int64_t(position.next_class));
  writer.set_attribute("exemplar_hash", identity.exemplar_hash);
  writer.set_attribute("hierarchy_hash", identity.hierarchy_hash);
  writer.commit();
}

SynthesisPosition load_synthesis(const par::Comm& comm, const io::CheckpointReader& reader,
                                 const std::vector<RetiledLevel>& pyramid,
                                 const SynthesisIdentity& identity,
                                 std::vector<LevelColours>& colours) {
  const std::string file = reader.path().string();
  if (reader.attribute_string("hierarchy_hash") != identity.hierarchy_hash)
    throw InputError(file + ": written for another mesh hierarchy (mesh, vertices, levels or "
                            "retiling differ); restart with the config that wrote it");
  if (reader.attribute_string("exemplar_hash") != identity.exemplar_hash)
    throw InputError(file + ": written for another exemplar (the image file changed?); restart "
                            "with the exemplar that wrote it");
  colours.resize(pyramid.size());
  for (std::size_t k = 0; k < pyramid.size(); ++k) {
    const auto n = std::uint64_t(pyramid[k].rank_offsets.back());
    if (!reader.has_dataset(level_name(k, "colour")) ||
        reader.global_count(level_name(k, "colour")) != n)
      throw InputError(log::cat(file, ": no colours of level ", k, " with ", n, " vertices"));
    const auto first = std::uint64_t(pyramid[k].rank_offsets[std::size_t(comm.rank)]);
    const auto count = std::uint64_t(pyramid[k].rank_offsets[std::size_t(comm.rank) + 1]) - first;
    colours[k].colours.resize(count);
    colours[k].pixels.resize(count);
    reader.read<float>(level_name(k, "colour"),
                       {reinterpret_cast<float*>(colours[k].colours.data()), 3 * count}, first,
                       count);
    reader.read<std::int32_t>(level_name(k, "pixel"), colours[k].pixels, first, count);
  }
  SynthesisPosition position;
  position.level = int(reader.attribute_int64("level"));
  position.pass = Pass(reader.attribute_int64("pass"));
  position.next_class = std::int32_t(reader.attribute_int64("next_class"));
  if (position.level < 0 || position.level >= int(pyramid.size()) ||
      (position.pass != Pass::extrapolate && position.pass != Pass::refine) ||
      position.next_class < 0)
    throw InputError(file + ": position (level, pass, class) outside this run");
  return position;
}

} // namespace texsim::pipelines::surface_synthesis
