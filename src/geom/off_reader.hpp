#pragma once
/// Reader for Object File Format (.off) surfaces, which VTK does not read.
#include "geom/triangle_mesh.hpp"

#include <filesystem>

namespace texsim::geom {

/// Reads an ASCII OFF file as it is (no repair): the header keyword OFF or COFF (the counts may
/// follow on the same line), then "vertices faces [edges]", then the vertices' x y z (further
/// numbers on the line, such as colours, are ignored) and the faces
/// "k i_1 ... i_k" with polygons fan-triangulated from i_1. '#' starts a comment. Throws
/// texsim::InputError naming the file and the line for a missing file, a bad header, counts that
/// the file cannot hold, a non-number, a face with fewer than 3 vertices or a truncated file.
TriangleMesh read_off(const std::filesystem::path& path);

} // namespace texsim::geom
