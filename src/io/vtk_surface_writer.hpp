#pragma once
/// Writing one SurfacePiece as a VTK XML file (.vtp or .vtu) in binary appended form, LZ4
/// compressed, which ParaView reads directly. LZ4 rather than zlib: on a 1M-point, 2M-triangle
/// surface (96 MB of arrays) zlib level 1 wrote 60 MB/s to a 30 MB file, LZ4 ~210 MB/s to 51 MB.
#include "io/surface_piece.hpp"

#include <filesystem>

namespace texsim::io {

/// Throws texsim::Error naming the piece if its arrays are inconsistent (coordinates not a
/// multiple of 3, a triangle index out of range, a field of the wrong length). Not collective.
void check_surface_piece(const SurfacePiece& piece);

/// Writes `piece` to `path` (its extension should match `format`) atomically (temporary name,
/// fsync, rename; see core/atomic_output.hpp): points as Float64, each field with its own type
/// (Float64, Int32 or Int64), connectivity as Int64. Throws texsim::Error naming the file if it
/// cannot be written; a file already at `path` is then left as it was. Not collective.
void write_surface(const std::filesystem::path& path, const SurfacePiece& piece,
                   SurfaceFormat format);

/// "vtp" or "vtu".
const char* surface_extension(SurfaceFormat format);

} // namespace texsim::io
