#pragma once
/// Estimating the memory a surface pipeline needs from its mesh config before building the mesh.
#include "core/memory_budget.hpp"
#include "geom/mesh_source.hpp"

#include <cstdint>
#include <string>

namespace texsim::geom {

/// Triangles of the mesh `source` describes after its subdivision_levels (4 per level): from the
/// file's header or text (check_mesh_file(), which also refuses a malformed file) or the
/// generator's parameters. Saturates at UINT64_MAX. Serial.
std::uint64_t estimated_triangles(const MeshSource& source);

/// Memory per rank of a pipeline whose every rank holds the whole mesh at `replicated_bytes` per
/// triangle and its own part at `distributed_bytes` per triangle divided among `ranks`. The key
/// named is `section_path`.subdivision_levels when subdivision is on, else the file or generator
/// key. Serial.
MemoryEstimate estimate_mesh_memory(const MeshSource& source, const std::string& section_path,
                                    int ranks, std::uint64_t replicated_bytes,
                                    std::uint64_t distributed_bytes);

} // namespace texsim::geom
