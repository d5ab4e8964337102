#pragma once
/// A surface with per-vertex arrays as a ParaView .vtp file, for tests of mesh_fields.
#include "geom/triangle_mesh.hpp"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace texsim::test {

/// One-component point array: its name and a value per vertex.
using PointArray = std::pair<std::string, std::vector<double>>;

/// Writes `mesh` with `arrays` as an ASCII .vtp (17 digits: the values read back exactly) and
/// returns `path`. Not collective.
std::filesystem::path write_vtp(const std::filesystem::path& path, const geom::TriangleMesh& mesh,
                                const std::vector<PointArray>& arrays);

} // namespace texsim::test
