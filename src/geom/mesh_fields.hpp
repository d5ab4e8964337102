#pragma once
/// Per-vertex arrays of a pipeline's input mesh file that its expressions may read by name
/// (`<pipeline>.mesh_fields: [width, ...]`): the names as the config gives them (their values at
/// points near the surface: geom/distributed_mesh_fields).
#include "core/config.hpp"
#include "geom/mesh_source.hpp"

#include <string>
#include <vector>

namespace texsim::geom {

/// `mesh_fields: [name, ...]` of `section`: point arrays of `mesh.file`, each a plain identifier
/// other than x, y, z. InputError naming the key for a generated mesh or a name expressions
/// cannot use.
std::vector<std::string> read_mesh_fields(const ConfigSection& section, const MeshSource& mesh);

} // namespace texsim::geom
