#include "pipelines/fem_rd/state_checkpoint.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"
#include "par/record_exchange.hpp"

#include <algorithm>

namespace texsim::pipelines::fem_rd {
namespace {

std::vector<double> owned_xyz(const geom::DistributedMesh& mesh,
                              const std::vector<geom::Vec3>& positions) {
  std::vector<double> xyz;
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v)
    xyz.insert(xyz.end(), positions[v].data(), positions[v].data() + 3);
  return xyz;
}

std::string species_dataset(const std::string& name) {
  return "species_" + name;
}

/// Rows [begin[r], begin[r+1]) of an n-row dataset for each of `ranks` ranks, as even as can be:
/// who reads which rows, and which rank keeps the rows of which input ids on their way.
std::vector<std::uint64_t> even_split(std::uint64_t n, int ranks) {
  std::vector<std::uint64_t> begin(std::size_t(ranks) + 1);
  for (int r = 0; r <= ranks; ++r)
    begin[r] = n * std::uint64_t(r) / std::uint64_t(ranks);
  return begin;
}

int rank_of(const std::vector<std::uint64_t>& split, std::uint64_t id) {
  return int(std::upper_bound(split.begin(), split.end(), id) - split.begin()) - 1;
}

/// What an owner asks the rank that keeps an input id's row for.
struct RowRequest {
  std::int64_t input_id;
  std::int32_t rank;
  std::int32_t owned_index;
};

} // namespace

void save_state(const io::CheckpointStore& store, std::int64_t step,
                const geom::DistributedMesh& mesh, const ReactionDiffusionSolver& solver,
                const GeometryState& geometry, const std::vector<ExtraColumn>& extra) {
  auto writer = store.begin(step);
  const std::uint64_t offset = std::uint64_t(mesh.owned_begin());
  const std::uint64_t count = std::uint64_t(mesh.global_count());
  const auto ids = mesh.owned_input_ids();
  writer.write<std::int64_t>("input_vertex_id", ids, offset, count);
  for (std::size_t s = 0; s < solver.species_count(); ++s)
    writer.write<double>(species_dataset(solver.species_names()[s]),
                         solver.local_values(s).first(mesh.owned_count()), offset, count);
  for (const ExtraColumn& column : extra)
    writer.write<double>(column.dataset, *column.owned, offset, count);
  writer.write<double>("positions", owned_xyz(mesh, geometry.positions), offset, count, 3);
  writer.write<double>("matrix_positions", owned_xyz(mesh, geometry.matrix_positions), offset,
                       count, 3);
  writer.commit();
}

std::int64_t load_state(const io::CheckpointReader& reader, const geom::DistributedMesh& mesh,
                        ReactionDiffusionSolver& solver, GeometryState& geometry,
                        const std::vector<ExtraColumn>& extra) {
  const par::Comm& comm = mesh.comm();
  const std::uint64_t n = std::uint64_t(mesh.global_count());
  if (!reader.has_dataset("input_vertex_id") || reader.global_count("input_vertex_id") != n)
    throw InputError(reader.path().string() + ": checkpoint of a mesh with a different vertex "
                                              "count; restart with the config that wrote it");
  std::vector<std::string> datasets;
  for (const auto& name : solver.species_names()) {
    if (!reader.has_dataset(species_dataset(name)))
      throw InputError(reader.path().string() + ": no values of species '" + name +
                       "' (written by another model)");
    datasets.push_back(species_dataset(name));
  }
  for (const ExtraColumn& column : extra) {
    if (!reader.has_dataset(column.dataset))
      throw InputError(reader.path().string() + ": no dataset '" + column.dataset +
                       "' (written by another model or version)");
    datasets.push_back(column.dataset);
  }
  const std::size_t species = solver.species_count();
  const std::size_t columns = datasets.size(); // species, then the extra columns
  const std::size_t width = columns + 6;       // and positions, matrix positions

  // This rank's share of the rows, as (input id, `width` values) records.
  const auto split = even_split(n, comm.size);
  const std::uint64_t first = split[comm.rank], rows = split[comm.rank + 1] - first;
  std::vector<std::int64_t> ids(rows);
  reader.read<std::int64_t>("input_vertex_id", ids, first, rows);
  std::vector<double> table(rows * width), column(rows), xyz(3 * rows);
  for (std::size_t c = 0; c < columns; ++c) {
    reader.read<double>(datasets[c], column, first, rows);
    for (std::uint64_t row = 0; row < rows; ++row)
      table[row * width + c] = column[row];
  }
  for (int which = 0; which < 2; ++which) {
    reader.read<double>(which == 0 ? "positions" : "matrix_positions", xyz, first, rows);
    for (std::uint64_t row = 0; row < rows; ++row)
      for (int axis = 0; axis < 3; ++axis)
        table[row * width + columns + 3 * which + axis] = xyz[3 * row + axis];
  }

  // Each row goes to the rank that keeps its input id's range...
  std::vector<std::vector<std::int64_t>> id_out(comm.size);
  std::vector<std::vector<double>> value_out(comm.size);
  par::run_collectively(comm, [&] {
    for (std::uint64_t row = 0; row < rows; ++row) {
      if (ids[row] < 0 || std::uint64_t(ids[row]) >= n)
        throw InputError(reader.path().string() + ": vertex id " + std::to_string(ids[row]) +
                         " out of range in input_vertex_id (damaged checkpoint)");
      const int keeper = rank_of(split, std::uint64_t(ids[row]));
      id_out[keeper].push_back(ids[row]);
      value_out[keeper].insert(value_out[keeper].end(), table.begin() + row * width,
                               table.begin() + (row + 1) * width);
    }
  });
  table = {};
  const auto kept_ids = par::exchange_records(comm, id_out);
  const auto kept_values = par::exchange_records(comm, value_out);
  const std::uint64_t kept_first = split[comm.rank];
  std::vector<std::int64_t> kept_row(split[comm.rank + 1] - kept_first, -1);
  for (std::size_t k = 0; k < kept_ids.size(); ++k)
    kept_row[std::uint64_t(kept_ids[k]) - kept_first] = std::int64_t(k);

  // ...and from there to the vertex's owner, which asks for it.
  std::vector<std::vector<RowRequest>> requests(comm.size);
  const auto owned_ids = mesh.owned_input_ids();
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v)
    requests[rank_of(split, std::uint64_t(owned_ids[v]))].push_back({owned_ids[v], comm.rank, v});
  const auto asked = par::exchange_records(comm, requests);
  std::vector<std::vector<std::int32_t>> index_out(comm.size);
  std::vector<std::vector<double>> answer_out(comm.size);
  par::run_collectively(comm, [&] {
    for (const auto& request : asked) {
      const std::int64_t k = kept_row[std::uint64_t(request.input_id) - kept_first];
      if (k < 0)
        throw InputError(reader.path().string() + ": no row for vertex id " +
                         std::to_string(request.input_id) + " (damaged checkpoint)");
      index_out[request.rank].push_back(request.owned_index);
      answer_out[request.rank].insert(answer_out[request.rank].end(),
                                      kept_values.begin() + k * std::int64_t(width),
                                      kept_values.begin() + (k + 1) * std::int64_t(width));
    }
  });
  const auto indices = par::exchange_records(comm, index_out);
  const auto answers = par::exchange_records(comm, answer_out);

  std::vector<std::vector<double>> owned(columns, std::vector<double>(mesh.owned_count()));
  const std::size_t local_vertices = mesh.mesh().positions.size();
  std::vector<double> positions(3 * local_vertices), matrix_positions(3 * local_vertices);
  for (std::size_t a = 0; a < indices.size(); ++a) {
    const double* row = answers.data() + a * width;
    const auto v = std::size_t(indices[a]);
    for (std::size_t c = 0; c < columns; ++c)
      owned[c][v] = row[c];
    std::copy(row + columns, row + columns + 3, positions.begin() + 3 * std::ptrdiff_t(v));
    std::copy(row + columns + 3, row + width, matrix_positions.begin() + 3 * std::ptrdiff_t(v));
  }
  for (std::size_t s = 0; s < species; ++s)
    solver.set_owned_values(s, owned[s]);
  for (std::size_t e = 0; e < extra.size(); ++e)
    *extra[e].owned = std::move(owned[species + e]);
  for (auto [values, target] : {std::pair{&positions, &geometry.positions},
                                std::pair{&matrix_positions, &geometry.matrix_positions}}) {
    mesh.update_halo(*values, 3);
    target->resize(local_vertices);
    for (std::size_t v = 0; v < local_vertices; ++v)
      (*target)[v] = geom::Vec3((*values)[3 * v], (*values)[3 * v + 1], (*values)[3 * v + 2]);
  }
  return reader.step();
}

} // namespace texsim::pipelines::fem_rd
