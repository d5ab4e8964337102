#include "geom/mesh_memory.hpp"

#include "geom/mesh_file_check.hpp"

namespace texsim::geom {
namespace {

std::uint64_t base_triangles(const MeshSource& source) {
  switch (source.generator) {
  case MeshGenerator::kNone:
    return check_mesh_file(source.file).faces;
  case MeshGenerator::kIcosphere:
    return saturating_multiply(20, std::uint64_t(1) << (2 * source.icosphere_level));
  case MeshGenerator::kTorus:
    return 2 * std::uint64_t(source.torus_segments[0]) * std::uint64_t(source.torus_segments[1]);
  case MeshGenerator::kBox:
    return 12 * std::uint64_t(source.box_cells_per_edge) * std::uint64_t(source.box_cells_per_edge);
  case MeshGenerator::kPlane:
    return 2 * std::uint64_t(source.box_cells_per_edge) * std::uint64_t(source.box_cells_per_edge);
  }
  return 0;
}

} // namespace

std::uint64_t estimated_triangles(const MeshSource& source) {
  std::uint64_t triangles = base_triangles(source);
  for (int level = 0; level < source.subdivision_levels; ++level)
    triangles = saturating_multiply(triangles, 4);
  return triangles;
}

MemoryEstimate estimate_mesh_memory(const MeshSource& source, const std::string& section_path,
                                    int ranks, std::uint64_t replicated_bytes,
                                    std::uint64_t distributed_bytes) {
  const std::uint64_t triangles = estimated_triangles(source);
  MemoryEstimate estimate;
  estimate.bytes =
      saturating_add(saturating_multiply(triangles, replicated_bytes),
                     saturating_multiply(triangles, distributed_bytes) / std::uint64_t(ranks));
  estimate.key = section_path + "." +
                 (source.subdivision_levels > 0              ? "subdivision_levels"
                  : source.generator == MeshGenerator::kNone ? "file"
                                                             : "generator");
  estimate.detail =
      std::to_string(triangles) + " triangles" +
      (source.subdivision_levels > 0
           ? " after " + std::to_string(source.subdivision_levels) + " Loop subdivision levels"
           : std::string()) +
      ", about " + std::to_string(replicated_bytes) + " bytes each on every rank" +
      (distributed_bytes > 0
           ? " and " + std::to_string(distributed_bytes) + " divided among the ranks"
           : std::string());
  return estimate;
}

} // namespace texsim::geom
