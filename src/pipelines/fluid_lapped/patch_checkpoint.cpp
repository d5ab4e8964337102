#include "pipelines/fluid_lapped/patch_checkpoint.hpp"

#include "core/error.hpp"
#include "pipelines/fluid_lapped/patch_exchange.hpp"

#include <mpi.h>

namespace texsim::pipelines::fluid_lapped {
namespace {

/// Sum of `local` over lower ranks, and over all ranks.
std::pair<std::uint64_t, std::uint64_t> offset_and_total(const par::Comm& comm,
                                                         std::uint64_t local) {
  std::uint64_t offset = 0, total = 0;
  MPI_Exscan(&local, &offset, 1, MPI_UINT64_T, MPI_SUM, comm.raw);
  if (comm.rank == 0)
    offset = 0;
  MPI_Allreduce(&local, &total, 1, MPI_UINT64_T, MPI_SUM, comm.raw);
  return {offset, total};
}

} // namespace

void save_patch_state(const par::Comm& comm, const io::CheckpointStore& store,
                      const PatchState& state, const std::string& inputs_hash) {
  const auto patches =
      exchange_patches(comm, state.patches, id_order_destinations(comm, state.patches));
  std::vector<std::int64_t> ids, vertex_counts, triangle_counts;
  std::vector<std::int32_t> births, surface_triangles, corners;
  std::vector<double> positions, uvs, weights;
  for (const auto& patch : patches) {
    ids.push_back(patch.id);
    births.push_back(patch.birth_frame);
    vertex_counts.push_back(std::int64_t(patch.positions.size()));
    triangle_counts.push_back(std::int64_t(patch.triangles.size()));
    for (std::size_t v = 0; v < patch.positions.size(); ++v) {
      positions.insert(positions.end(),
                       {patch.positions[v].x(), patch.positions[v].y(), patch.positions[v].z()});
      uvs.insert(uvs.end(), {patch.rest_uv[v].x(), patch.rest_uv[v].y()});
      weights.push_back(patch.weights[v]);
      surface_triangles.push_back(patch.surface_triangle[v]);
    }
    for (const auto& t : patch.triangles)
      corners.insert(corners.end(), {t[0], t[1], t[2]});
  }
  auto writer = store.begin(std::int64_t(state.frame) + 1);
  const auto [patch_offset, patch_total] = offset_and_total(comm, ids.size());
  const auto [vertex_offset, vertex_total] = offset_and_total(comm, weights.size());
  const auto [triangle_offset, triangle_total] = offset_and_total(comm, corners.size() / 3);
  writer.write<std::int64_t>("patch_id", ids, patch_offset, patch_total);
  writer.write<std::int32_t>("patch_birth_frame", births, patch_offset, patch_total);
  writer.write<std::int64_t>("patch_vertex_count", vertex_counts, patch_offset, patch_total);
  writer.write<std::int64_t>("patch_triangle_count", triangle_counts, patch_offset, patch_total);
  writer.write<double>("vertex_position", positions, vertex_offset, vertex_total, 3);
  writer.write<double>("vertex_rest_uv", uvs, vertex_offset, vertex_total, 2);
  writer.write<double>("vertex_weight", weights, vertex_offset, vertex_total);
  writer.write<std::int32_t>("vertex_surface_triangle", surface_triangles, vertex_offset,
                             vertex_total);
  writer.write<std::int32_t>("triangle_corners", corners, triangle_offset, triangle_total, 3);
  writer.set_attribute("frame", std::int64_t(state.frame));
  writer.set_attribute("next_patch_id", state.next_id);
  writer.set_attribute("inputs_hash", inputs_hash);
  writer.commit();
}

PatchState load_patch_state(const par::Comm& comm, const io::CheckpointReader& reader,
                            const std::string& inputs_hash) {
  const std::string file = reader.path().string();
  if (!reader.has_attribute("inputs_hash") || reader.attribute_string("inputs_hash") != inputs_hash)
    throw InputError(file + ": written for other frames or another exemplar (an input file "
                            "changed?); restart with the inputs that wrote it");
  for (const char* name : {"patch_id", "patch_birth_frame", "patch_vertex_count",
                           "patch_triangle_count", "vertex_position", "vertex_rest_uv",
                           "vertex_weight", "vertex_surface_triangle", "triangle_corners"})
    if (!reader.has_dataset(name))
      throw InputError(file + ": no dataset " + name + " (not a fluid_lapped checkpoint)");
  // Every rank reads the per-patch counts (small), then its own run of patches.
  const auto patch_total = reader.global_count("patch_id");
  std::vector<std::int64_t> vertex_counts(patch_total), triangle_counts(patch_total);
  reader.read<std::int64_t>("patch_vertex_count", vertex_counts, 0, patch_total);
  reader.read<std::int64_t>("patch_triangle_count", triangle_counts, 0, patch_total);
  const std::uint64_t first = patch_total * std::uint64_t(comm.rank) / std::uint64_t(comm.size);
  const std::uint64_t last = patch_total * std::uint64_t(comm.rank + 1) / std::uint64_t(comm.size);
  std::uint64_t vertex_first = 0, triangle_first = 0;
  for (std::uint64_t p = 0; p < first; ++p) {
    vertex_first += std::uint64_t(vertex_counts[p]);
    triangle_first += std::uint64_t(triangle_counts[p]);
  }
  std::uint64_t vertex_count = 0, triangle_count = 0;
  for (std::uint64_t p = first; p < last; ++p) {
    vertex_count += std::uint64_t(vertex_counts[p]);
    triangle_count += std::uint64_t(triangle_counts[p]);
  }
  if (reader.global_count("vertex_position") < vertex_first + vertex_count ||
      reader.global_count("triangle_corners") < triangle_first + triangle_count)
    throw InputError(file + ": patch counts do not match the vertex and triangle arrays");
  std::vector<std::int64_t> ids(last - first);
  std::vector<std::int32_t> births(last - first), surface_triangles(vertex_count),
      corners(3 * triangle_count);
  std::vector<double> positions(3 * vertex_count), uvs(2 * vertex_count), weights(vertex_count);
  reader.read<std::int64_t>("patch_id", ids, first, last - first);
  reader.read<std::int32_t>("patch_birth_frame", births, first, last - first);
  reader.read<double>("vertex_position", positions, vertex_first, vertex_count);
  reader.read<double>("vertex_rest_uv", uvs, vertex_first, vertex_count);
  reader.read<double>("vertex_weight", weights, vertex_first, vertex_count);
  reader.read<std::int32_t>("vertex_surface_triangle", surface_triangles, vertex_first,
                            vertex_count);
  reader.read<std::int32_t>("triangle_corners", corners, triangle_first, triangle_count);

  PatchState state;
  state.frame = std::int32_t(reader.attribute_int64("frame"));
  state.next_id = reader.attribute_int64("next_patch_id");
  std::size_t v = 0, t = 0;
  for (std::uint64_t p = first; p < last; ++p) {
    Patch patch;
    patch.id = ids[p - first];
    patch.birth_frame = births[p - first];
    const auto n = std::size_t(vertex_counts[p]);
    for (std::size_t k = 0; k < n; ++k, ++v) {
      patch.positions.emplace_back(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
      patch.rest_uv.emplace_back(uvs[2 * v], uvs[2 * v + 1]);
      patch.weights.push_back(weights[v]);
      patch.surface_triangle.push_back(surface_triangles[v]);
    }
    for (std::int64_t k = 0; k < triangle_counts[p]; ++k, ++t) {
      const geom::Triangle corner{corners[3 * t], corners[3 * t + 1], corners[3 * t + 2]};
      for (const auto c : corner)
        if (c < 0 || std::size_t(c) >= n)
          throw InputError(file + ": a triangle of patch " + std::to_string(patch.id) +
                           " refers to a vertex it does not have");
      patch.triangles.push_back(corner);
    }
    state.patches.push_back(std::move(patch));
  }
  return state;
}

} // namespace texsim::pipelines::fluid_lapped
