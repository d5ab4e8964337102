#include "vol/parallel_vti_writer.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "par/collective.hpp"
#include "vol/vti_io.hpp"

#include <mpi.h>

#include <filesystem>
#include <iomanip>
#include <sstream>
#include <vector>

namespace texsim::vol {
namespace {

std::string piece_name(const std::string& basename, int rank) {
  return basename + "_" + std::to_string(rank) + ".vti";
}

/// The .pvti text: the whole extent, and one Piece per rank that wrote one (extent z range
/// [first, last] in `pieces`, -1 for none).
template <class Grid>
std::string pvti_text(const std::string& basename, const std::array<int, 3>& whole,
                      const Grid& any_piece, const std::string& array_name,
                      const std::vector<int>& pieces) {
  std::ostringstream xml;
  xml << std::setprecision(17);
  const auto& spacing = any_piece.spacing();
  const auto& origin = any_piece.origin();
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
      << "  <PImageData WholeExtent=\"0 " << whole[0] - 1 << " 0 " << whole[1] - 1 << " 0 "
      << whole[2] - 1 << "\" GhostLevel=\"0\" Origin=\"" << origin[0] << " " << origin[1] << " "
      << origin[2] << "\" Spacing=\"" << spacing[0] << " " << spacing[1] << " " << spacing[2]
      << "\">\n"
      << "    <PPointData>\n"
      << "      <PDataArray type=\"Float32\" Name=\"" << array_name << "\" NumberOfComponents=\""
      << voxel_components<typename Grid::value_type> << "\"/>\n"
      << "    </PPointData>\n";
  for (std::size_t rank = 0; rank < pieces.size() / 2; ++rank)
    if (pieces[2 * rank] >= 0)
      xml << "    <Piece Extent=\"0 " << whole[0] - 1 << " 0 " << whole[1] - 1 << " "
          << pieces[2 * rank] << " " << pieces[2 * rank + 1] << "\" Source=\"" << basename << "/"
          << piece_name(basename, static_cast<int>(rank)) << "\"/>\n";
  xml << "  </PImageData>\n</VTKFile>\n";
  return xml.str();
}

template <class Grid>
std::filesystem::path write_pieces(const par::Comm& comm, const std::filesystem::path& dir,
                                   const std::string& basename, const VolumePiece<Grid>& piece,
                                   const std::array<int, 3>& whole, const std::string& array_name) {
  const auto pvti = dir / (basename + ".pvti");
  int range[2] = {-1, -1};
  par::run_collectively(comm, [&] {
    if (piece.piece == nullptr)
      return;
    const Dims dims = piece.piece->dims();
    TEXSIM_VERIFY(dims.nx == whole[0] && dims.ny == whole[1] && piece.z_first >= 0 &&
                      piece.z_first + dims.nz <= whole[2],
                  pvti.string() << ": piece of " << dims.nx << " x " << dims.ny << " x " << dims.nz
                                << " at z " << piece.z_first << " outside the whole image");
    std::filesystem::create_directories(dir / basename);
    write_vti(dir / basename / piece_name(basename, comm.rank), *piece.piece, array_name,
              piece.z_first);
    range[0] = piece.z_first;
    range[1] = piece.z_first + dims.nz - 1;
  });
  std::vector<int> ranges(comm.is_root() ? 2 * static_cast<std::size_t>(comm.size) : 0);
  MPI_Gather(range, 2, MPI_INT, ranges.data(), 2, MPI_INT, 0, comm.raw);
  // Rank 0's spacing and origin stand for all: it always holds a piece (the lowest planes).
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    TEXSIM_VERIFY(piece.piece != nullptr, pvti.string() << ": rank 0 has no piece");
    write_atomically(pvti, pvti_text(basename, whole, *piece.piece, array_name, ranges));
  });
  return pvti;
}

} // namespace

std::filesystem::path write_parallel_vti(const par::Comm& comm, const std::filesystem::path& dir,
                                         const std::string& basename,
                                         const VolumePiece<ScalarGrid>& piece,
                                         const std::array<int, 3>& whole,
                                         const std::string& array_name) {
  return write_pieces(comm, dir, basename, piece, whole, array_name);
}

std::filesystem::path write_parallel_vti(const par::Comm& comm, const std::filesystem::path& dir,
                                         const std::string& basename,
                                         const VolumePiece<RgbGrid>& piece,
                                         const std::array<int, 3>& whole,
                                         const std::string& array_name) {
  return write_pieces(comm, dir, basename, piece, whole, array_name);
}

} // namespace texsim::vol
