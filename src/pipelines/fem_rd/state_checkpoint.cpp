#include "pipelines/fem_rd/state_checkpoint.hpp"

#include "core/error.hpp"

#include <unordered_map>

namespace texsim::pipelines::fem_rd {
namespace {

std::vector<double> owned_xyz(const geom::DistributedMesh& mesh,
                              const std::vector<geom::Vec3>& positions) {
  std::vector<double> xyz;
  for (std::int32_t g = mesh.owned_begin(); g < mesh.owned_end(); ++g)
    xyz.insert(xyz.end(), positions[g].data(), positions[g].data() + 3);
  return xyz;
}

std::string species_dataset(const std::string& name) {
  return "species_" + name;
}

} // namespace

void save_state(const io::CheckpointStore& store, std::int64_t step,
                const geom::DistributedMesh& mesh, const ReactionDiffusionSolver& solver,
                const GeometryState& geometry) {
  auto writer = store.begin(step);
  const std::uint64_t offset = std::uint64_t(mesh.owned_begin());
  const std::uint64_t count = std::uint64_t(mesh.global_count());
  const std::vector<std::int64_t> ids(mesh.input_id().begin() + mesh.owned_begin(),
                                      mesh.input_id().begin() + mesh.owned_end());
  writer.write<std::int64_t>("input_vertex_id", ids, offset, count);
  for (std::size_t s = 0; s < solver.species_count(); ++s)
    writer.write<double>(species_dataset(solver.species_names()[s]),
                         solver.local_values(s).first(mesh.owned_count()), offset, count);
  writer.write<double>("positions", owned_xyz(mesh, geometry.positions), offset, count, 3);
  writer.write<double>("matrix_positions", owned_xyz(mesh, geometry.matrix_positions), offset,
                       count, 3);
  writer.commit();
}

std::int64_t load_state(const io::CheckpointReader& reader, const geom::DistributedMesh& mesh,
                        ReactionDiffusionSolver& solver, GeometryState& geometry) {
  const std::uint64_t n = std::uint64_t(mesh.global_count());
  if (!reader.has_dataset("input_vertex_id") || reader.global_count("input_vertex_id") != n)
    throw InputError(reader.path().string() + ": checkpoint of a mesh with a different vertex "
                                              "count; restart with the config that wrote it");
  // Every rank reads the whole arrays and picks its vertices by input id: the checkpoint may come
  // from another partition.
  std::vector<std::int64_t> ids(n);
  reader.read<std::int64_t>("input_vertex_id", ids, 0, n);
  std::vector<std::int64_t> row_of_input(n, -1);
  for (std::uint64_t row = 0; row < n; ++row)
    row_of_input.at(std::size_t(ids[row])) = std::int64_t(row);

  std::vector<double> all(n), owned(mesh.owned_count());
  for (std::size_t s = 0; s < solver.species_count(); ++s) {
    const std::string name = species_dataset(solver.species_names()[s]);
    if (!reader.has_dataset(name))
      throw InputError(reader.path().string() + ": no values of species '" +
                       solver.species_names()[s] + "' (written by another model)");
    reader.read<double>(name, all, 0, n);
    for (std::int32_t v = 0; v < mesh.owned_count(); ++v)
      owned[v] = all[row_of_input[mesh.input_id()[mesh.owned_begin() + v]]];
    solver.set_owned_values(s, owned);
  }
  std::vector<double> xyz(3 * n);
  for (auto* target : {&geometry.positions, &geometry.matrix_positions}) {
    reader.read<double>(target == &geometry.positions ? "positions" : "matrix_positions", xyz, 0,
                        n);
    target->resize(n);
    for (std::uint64_t g = 0; g < n; ++g) {
      const auto row = std::size_t(row_of_input[mesh.input_id()[g]]);
      (*target)[g] = geom::Vec3(xyz[3 * row], xyz[3 * row + 1], xyz[3 * row + 2]);
    }
  }
  return reader.step();
}

} // namespace texsim::pipelines::fem_rd
