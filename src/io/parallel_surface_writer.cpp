#include "io/parallel_surface_writer.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "io/parallel_array_declarations.hpp"
#include "io/vtk_surface_writer.hpp"
#include "io/xml_escape.hpp"
#include "par/collective.hpp"

#include <functional>
#include <sstream>

namespace texsim::io {
namespace {

std::string piece_file_name(const std::string& basename, int rank, SurfaceFormat format) {
  return basename + "_" + std::to_string(rank) + "." + surface_extension(format);
}

/// Names, components and types of the fields, to check that all ranks declare the same arrays.
std::string field_signature(const SurfacePiece& piece) {
  std::string signature;
  signature += "t:" + piece.texture_coordinates + ";";
  for (const auto& field : piece.point_fields)
    signature += "p:" + field.name + ":" + std::to_string(field.components) + ":" +
                 field.vtk_type_name() + ";";
  for (const auto& field : piece.cell_fields)
    signature += "c:" + field.name + ":" + std::to_string(field.components) + ":" +
                 field.vtk_type_name() + ";";
  return signature;
}

/// The .pvtu/.pvtp file: the arrays every piece holds and the pieces' relative paths.
std::string parallel_header(const SurfacePiece& piece, const std::string& basename, int pieces,
                            SurfaceFormat format) {
  const char* type = format == SurfaceFormat::vtp ? "PPolyData" : "PUnstructuredGrid";
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"" << type
      << "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <" << type << " GhostLevel=\"0\">\n";
  write_array_declarations(xml, "PPointData", piece.point_fields, piece.texture_coordinates);
  write_array_declarations(xml, "PCellData", piece.cell_fields);
  xml << "    <PPoints>\n"
      << "      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
      << "    </PPoints>\n";
  for (int rank = 0; rank < pieces; ++rank)
    xml << "    <Piece Source=\"" << xml_escape(basename) << "/"
        << xml_escape(piece_file_name(basename, rank, format)) << "\"/>\n";
  xml << "  </" << type << ">\n"
      << "</VTKFile>\n";
  return xml.str();
}

} // namespace

std::filesystem::path write_parallel_surface(const par::Comm& comm,
                                             const std::filesystem::path& directory,
                                             const std::string& basename, const SurfacePiece& piece,
                                             SurfaceFormat format) {
  const auto piece_directory = directory / basename;
  const auto header_path = directory / (basename + ".p" + std::string(surface_extension(format)));

  const std::uint64_t signature = std::hash<std::string>{}(field_signature(piece));
  std::uint64_t lowest = 0, highest = 0;
  MPI_Allreduce(&signature, &lowest, 1, MPI_UINT64_T, MPI_MIN, comm.raw);
  MPI_Allreduce(&signature, &highest, 1, MPI_UINT64_T, MPI_MAX, comm.raw);

  par::run_collectively(comm, [&] {
    TEXSIM_VERIFY(lowest == highest, header_path.string()
                                         << ": ranks declare different point/cell fields");
    check_surface_piece(piece);
    if (comm.is_root()) {
      std::error_code error;
      std::filesystem::create_directories(piece_directory, error);
      TEXSIM_VERIFY(!error, piece_directory.string()
                                << ": cannot create output directory (" << error.message() << ")");
    }
  });
  par::run_collectively(comm, [&] {
    write_surface(piece_directory / piece_file_name(basename, comm.rank, format), piece, format);
  });
  par::run_collectively(comm, [&] {
    if (comm.is_root())
      write_atomically(header_path, parallel_header(piece, basename, comm.size, format));
  });
  return header_path;
}

} // namespace texsim::io
