#pragma once
/// Writing a textured triangle surface as Wavefront OBJ with its material library (.mtl), the
/// format every modeller and viewer opens with the texture applied.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace texsim::io {

/// A triangle surface with texture coordinates at its triangle corners, as plain arrays (io does
/// not depend on geom). Not owned: the caller keeps the arrays alive while writing.
struct TexturedSurface {
  std::span<const double> xyz;             ///< 3 coordinates per vertex, model units
  std::span<const std::int32_t> triangles; ///< 3 vertex indices (from 0) per triangle
  /// 6 values per triangle: (u, v) of its corners in the triangle's corner order, v = 0 at the
  /// bottom of the texture image (the OBJ convention).
  std::span<const double> corner_uv;
  /// Optional unit normals, 3 per vertex (written as vn), or empty for none.
  std::span<const double> normals;
};

/// The material the .obj uses: its name and the image shown as its diffuse colour (map_Kd), a
/// path relative to the .obj's directory.
struct ObjMaterial {
  std::string name = "atlas";
  std::string texture_file = "atlas.png";
};

/// Writes `obj_path` (e.g. "textured.obj") and, beside it, the material library of the same stem
/// with extension .mtl ("textured.mtl", referenced by `mtllib`), each atomically (temporary name,
/// fsync, rename; see core/atomic_output.hpp), the .mtl first. Vertices are written as `v` lines
/// in order; each distinct (vertex, uv) pair of the triangle corners becomes one `vt` line, in
/// order of first use; faces are `f v/vt` (`f v/vt/vn` with normals), 1-based. Numbers are
/// written in the shortest form that reads back to the same double. Throws texsim::Error naming
/// the file for inconsistent arrays (sizes, an index out of range, a non-finite value), a material
/// name or texture path that OBJ cannot hold (empty, spaces or line breaks), or a failed write;
/// files already at the paths are then left as they were. Not collective.
void write_textured_obj(const std::filesystem::path& obj_path, const TexturedSurface& surface,
                        const ObjMaterial& material = {});

} // namespace texsim::io
