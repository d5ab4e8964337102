#pragma once
/// Per-vertex arrays of a pipeline's input mesh file that its expressions may read by name
/// (`<pipeline>.mesh_fields: [width, ...]`): the names as the config gives them, and their values
/// at any point near the surface the mesh section builds (refined, scaled, remeshed or noisy).
#include "core/config.hpp"
#include "geom/mesh_source.hpp"
#include "geom/surface_field_sampler.hpp"

#include <string>
#include <vector>

namespace texsim::geom {

/// `mesh_fields: [name, ...]` of `section`: point arrays of `mesh.file`, each a plain identifier
/// other than x, y, z. InputError naming the key for a generated mesh or a name expressions
/// cannot use.
std::vector<std::string> read_mesh_fields(const ConfigSection& section, const MeshSource& mesh);

/// The arrays `names` of `mesh.file` on its surface scaled by `mesh.scale`, field k in the order
/// of `names`. InputError naming the file for a missing array or a format without arrays.
/// Serial: every rank that calls it reads the file.
SurfaceFieldSampler load_mesh_fields(const MeshSource& mesh, const std::vector<std::string>& names);

} // namespace texsim::geom
