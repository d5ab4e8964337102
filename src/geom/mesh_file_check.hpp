#pragma once
/// Checking a mesh file's structure before VTK reads it. VTK's PLY reader aborts or crashes on a
/// header whose counts exceed the body, its STL reader accepts a binary file shorter than its
/// triangle count says, and its OBJ reader reads "nan" as 0: these files are refused here, with
/// a message naming the file and what was found.
#include <cstdint>
#include <filesystem>

namespace texsim::geom {

/// Element counts a mesh file declares (exact for .ply .stl .obj .off; estimated from the file
/// size for VTK's own formats).
struct MeshFileCounts {
  std::uint64_t vertices = 0;
  std::uint64_t faces = 0;
  /// A PLY file whose last text line (ASCII body or header) has no '\n': VTK 9.1's reader scans
  /// past the end of such a line, so the reader must be given the text with one appended.
  bool ply_needs_final_newline = false;
};

/// Checks the file by its extension: .ply (header grammar, `end_header`, supported property
/// types, a vertex element with x, y, z and a face element with a list property; then the body,
/// ASCII or binary, walked element by element: every declared value present, coordinates finite,
/// face indices within the vertex count), .stl (binary: size 84 + 50 x the triangle count in the
/// header; ASCII: finite vertex coordinates), .obj (finite `v` coordinates, face indices within
/// the vertex count) and .off (header counts only; read_off() checks the rest). Other extensions
/// are only sized. Throws InputError naming the file. Serial.
MeshFileCounts check_mesh_file(const std::filesystem::path& path);

} // namespace texsim::geom
