#include "io/parallel_image_data_writer.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "io/image_data_writer.hpp"
#include "io/parallel_array_declarations.hpp"
#include "io/xml_escape.hpp"
#include "par/collective.hpp"

#include <mpi.h>

#include <algorithm>
#include <sstream>

namespace texsim::io {
namespace {

std::string piece_file_name(const std::string& basename, int strip) {
  return basename + "_" + std::to_string(strip) + ".vti";
}

/// Rows [first, last] of strip s, the last one shared with the next strip.
std::pair<int, int> strip_rows_of(int strip, int strip_rows, int height) {
  return {strip * strip_rows, std::min((strip + 1) * strip_rows, height - 1)};
}

/// The .pvti: the whole extent, the arrays, and every strip's piece with its extent (VTK's rows
/// run bottom to top).
std::string pvti_text(const std::string& basename, int width, int height, int strip_rows,
                      const std::vector<DataField>& fields) {
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
      << "  <PImageData WholeExtent=\"0 " << width - 1 << " 0 " << height - 1
      << " 0 0\" GhostLevel=\"0\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n";
  write_array_declarations(xml, "PPointData", fields);
  const int strips = (height + strip_rows - 1) / strip_rows;
  for (int s = 0; s < strips; ++s) {
    const auto [first, last] = strip_rows_of(s, strip_rows, height);
    xml << "    <Piece Extent=\"0 " << width - 1 << " " << height - 1 - last << " "
        << height - 1 - first << " 0 0\" Source=\"" << xml_escape(basename) << "/"
        << xml_escape(piece_file_name(basename, s)) << "\"/>\n";
  }
  xml << "  </PImageData>\n</VTKFile>\n";
  return xml.str();
}

} // namespace

std::filesystem::path write_parallel_image_data(const par::Comm& comm,
                                                const std::filesystem::path& dir,
                                                const std::string& basename, int width, int height,
                                                int strip_rows, const ImageStrips& strips) {
  const auto pvti = dir / (basename + ".pvti");
  TEXSIM_VERIFY(width > 0 && height > 0 && strip_rows > 0,
                pvti.string() << ": image of " << width << " x " << height
                              << " pixels in strips of " << strip_rows << " rows");
  const int strip_count = (height + strip_rows - 1) / strip_rows;
  int held = strips.count;
  MPI_Allreduce(MPI_IN_PLACE, &held, 1, MPI_INT, MPI_SUM, comm.raw);
  TEXSIM_VERIFY(held == strip_count,
                pvti.string() << ": the ranks hold " << held << " of " << strip_count << " strips");
  par::run_collectively(comm, [&] {
    if (strips.count == 0)
      return;
    TEXSIM_VERIFY(strips.first_strip >= 0 && strips.first_strip + strips.count <= strip_count,
                  pvti.string() << ": strips " << strips.first_strip << " .. "
                                << strips.first_strip + strips.count - 1 << " of " << strip_count);
    const int first_row = strip_rows_of(strips.first_strip, strip_rows, height).first;
    const int last_row =
        strip_rows_of(strips.first_strip + strips.count - 1, strip_rows, height).second;
    std::filesystem::create_directories(dir / basename);
    for (int s = strips.first_strip; s < strips.first_strip + strips.count; ++s) {
      const auto [first, last] = strip_rows_of(s, strip_rows, height);
      std::vector<DataField> rows;
      for (const auto& field : strips.point_fields) {
        TEXSIM_VERIFY(field.size() == std::size_t(field.components) * std::size_t(width) *
                                          std::size_t(last_row - first_row + 1),
                      pvti.string() << ": field '" << field.name << "' has " << field.size()
                                    << " values for rows " << first_row << " .. " << last_row);
        rows.push_back(field.tuples(std::size_t(first - first_row) * std::size_t(width),
                                    std::size_t(last - first + 1) * std::size_t(width)));
      }
      write_image_data_piece(dir / basename / piece_file_name(basename, s), width, last - first + 1,
                             first, height, rows);
    }
  });
  par::run_collectively(comm, [&] {
    if (!comm.is_root())
      return;
    std::filesystem::create_directories(dir);
    write_atomically(pvti, pvti_text(basename, width, height, strip_rows, strips.point_fields));
  });
  return pvti;
}

} // namespace texsim::io
