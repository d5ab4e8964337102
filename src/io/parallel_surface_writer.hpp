#pragma once
/// Writing a surface distributed over ranks as one ParaView dataset: every rank writes its piece
/// to <dir>/<basename>/<basename>_<rank>.vtu (or .vtp) and rank 0 writes <dir>/<basename>.pvtu
/// (or .pvtp), which lists the pieces and their arrays; ParaView opens the .pvtu as one surface.
#include "io/surface_piece.hpp"
#include "par/comm.hpp"

#include <filesystem>
#include <string>

namespace texsim::io {

/// Writes this rank's `piece` and, on rank 0, the header; returns the header's path (on every
/// rank). All ranks must give the same field names and components in the same order; a piece may
/// be empty. Fields keep their types (Float64, Int32, Int64) in the pieces and the header. Every
/// file is written atomically (core/atomic_output.hpp), replacing files of the same names.
/// Collective: a failure on any rank (unwritable directory, inconsistent piece) is raised as the
/// same texsim::Error on every rank.
std::filesystem::path write_parallel_surface(const par::Comm& comm,
                                             const std::filesystem::path& directory,
                                             const std::string& basename, const SurfacePiece& piece,
                                             SurfaceFormat format);

} // namespace texsim::io
