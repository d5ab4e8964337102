#pragma once
/// Reading triangle surfaces from user files.
#include "geom/mesh_validation.hpp"
#include "geom/triangle_mesh.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace texsim::geom {

/// Reads a surface by its extension (case-insensitive): .obj .ply .stl .vtk .vtp .vtu through
/// VTK's readers (polygons and strips triangulated; points, lines and volume cells' interiors
/// dropped, the surface of .vtu/.vtk volume cells kept), .off through read_off(). Returns the
/// file's mesh as stored, without repair. Throws texsim::InputError naming the file for a missing
/// file, an unknown extension, a file its reader cannot parse, and a file without triangles.
/// Serial.
TriangleMesh read_raw_mesh(const std::filesystem::path& path);

/// read_raw_mesh() followed by repair() with `options`; when `report` is not null (not owned) it
/// receives what was repaired, for the caller to log. Throws texsim::InputError as both do.
TriangleMesh read_mesh(const std::filesystem::path& path, const MeshRepairOptions& options = {},
                       RepairReport* report = nullptr);

/// A surface with values at its vertices, as stored in a file (no repair).
struct VertexFields {
  TriangleMesh mesh;
  std::vector<std::vector<double>> values; ///< [field][vertex of mesh]
};

/// The one-component point arrays `names` of a .vtp, .vtu or .vtk file, with the file's
/// triangles. Throws texsim::InputError naming the file for another format, a missing array
/// (listing the arrays the file has) and non-finite values. Serial.
VertexFields read_vertex_fields(const std::filesystem::path& path,
                                const std::vector<std::string>& names);

/// A surface with one 3-component point array (a velocity, such as OpenFOAM's U), as stored.
struct VertexVectors {
  TriangleMesh mesh;
  std::vector<Vec3> values; ///< per vertex of mesh
};

/// The 3-component point array `name` of a .vtp, .vtu or .vtk file, with the file's triangles.
/// Throws texsim::InputError naming the file as read_vertex_fields() does.
VertexVectors read_vertex_vectors(const std::filesystem::path& path, const std::string& name);

} // namespace texsim::geom
