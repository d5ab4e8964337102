#pragma once
/// A volume split in z over ranks, written as ParaView writes it in parallel: one .vti piece per
/// rank in <dir>/<basename>/ and <dir>/<basename>.pvti naming them, so no rank ever holds the
/// whole volume. ParaView (and vol::read_vti) opens the .pvti as one image.
#include "par/comm.hpp"
#include "vol/dense_grid.hpp"

#include <array>
#include <filesystem>
#include <string>

namespace texsim::vol {

/// This rank's part of the image: planes z_first .. z_first + piece->dims().nz - 1 of a whole
/// image of `whole` points per axis (x and y whole), or nothing (nullptr). Pieces should share
/// their boundary plane with the next piece, as VTK's point data does, or ParaView draws a gap.
template <class Grid> struct VolumePiece {
  const Grid* piece = nullptr;
  int z_first = 0;
};

/// Writes every rank's piece (atomically, core/atomic_output.hpp) and, on rank 0, the .pvti with
/// the pieces' extents and the piece's spacing and origin (those of the whole image). Returns the
/// .pvti's path. Collective; an error on any rank is raised on all.
std::filesystem::path write_parallel_vti(const par::Comm& comm, const std::filesystem::path& dir,
                                         const std::string& basename,
                                         const VolumePiece<ScalarGrid>& piece,
                                         const std::array<int, 3>& whole,
                                         const std::string& array_name);
std::filesystem::path write_parallel_vti(const par::Comm& comm, const std::filesystem::path& dir,
                                         const std::string& basename,
                                         const VolumePiece<RgbGrid>& piece,
                                         const std::array<int, 3>& whole,
                                         const std::string& array_name);

} // namespace texsim::vol
