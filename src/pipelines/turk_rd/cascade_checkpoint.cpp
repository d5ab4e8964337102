#include "pipelines/turk_rd/cascade_checkpoint.hpp"

#include "core/error.hpp"

namespace texsim::pipelines::turk_rd {

void save_cascade(const io::CheckpointStore& store, std::int64_t step,
                  const geom::SurfaceCells& cells, const CascadeState& state) {
  auto writer = store.begin(step);
  const std::uint64_t offset = std::uint64_t(cells.owned_begin());
  const std::uint64_t count = std::uint64_t(cells.global_count());
  writer.write<std::int64_t>("cell_id", cells.ids(), offset, count);
  for (const auto& [name, values] : state.fields)
    writer.write<double>("field_" + name, values, offset, count);
  writer.set_attribute("stage", std::int64_t(state.stage));
  writer.set_attribute("stage_step", state.stage_step);
  writer.commit();
}

CascadeState load_cascade(const io::CheckpointReader& reader, const geom::SurfaceCells& cells,
                          const std::vector<std::string>& expected_fields) {
  const std::uint64_t n = std::uint64_t(cells.global_count());
  if (!reader.has_dataset("cell_id") || reader.global_count("cell_id") != n)
    throw InputError(reader.path().string() +
                     ": checkpoint of a run with a different cell count; restart with the "
                     "config that wrote it");
  // Every rank reads whole arrays and picks its cells by id: the checkpoint may come from
  // another partition.
  std::vector<std::int64_t> ids(n);
  reader.read<std::int64_t>("cell_id", ids, 0, n);
  std::vector<std::int64_t> row_of_id(n, -1);
  for (std::uint64_t row = 0; row < n; ++row) {
    if (ids[row] < 0 || std::uint64_t(ids[row]) >= n)
      throw InputError(reader.path().string() + ": cell id " + std::to_string(ids[row]) +
                       " out of range");
    row_of_id[std::size_t(ids[row])] = std::int64_t(row);
  }
  CascadeState state;
  state.stage = std::size_t(reader.attribute_int64("stage"));
  state.stage_step = reader.attribute_int64("stage_step");
  std::vector<double> all(n);
  for (const auto& name : expected_fields) {
    if (!reader.has_dataset("field_" + name))
      throw InputError(reader.path().string() + ": no values of '" + name +
                       "' (written by another cascade)");
    reader.read<double>("field_" + name, all, 0, n);
    auto& owned = state.fields[name];
    for (const std::int64_t id : cells.ids())
      owned.push_back(all[std::size_t(row_of_id[std::size_t(id)])]);
  }
  return state;
}

} // namespace texsim::pipelines::turk_rd
