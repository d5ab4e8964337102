#pragma once
/// Writing per-pixel data of a 2D image (ids, ages, coordinates) as VTK image data (.vti), with
/// each array's own type, so ParaView shows integer ids exactly.
#include "io/surface_piece.hpp"

#include <filesystem>
#include <vector>

namespace texsim::io {

/// Writes a width x height image (one z slice, spacing 1, origin 0) with `point_fields`, each
/// holding components x width x height values row-major with row 0 at the TOP (as in images and
/// PNG files); rows are flipped into VTK's bottom-up order, so the .vti lies over the PNG of the
/// same pixels in ParaView. Binary, LZ4-compressed, written atomically. Throws texsim::Error
/// naming the file when a field has the wrong size or the file cannot be written. Not collective.
void write_image_data(const std::filesystem::path& path, int width, int height,
                      const std::vector<DataField>& point_fields);

/// The same for rows first_row .. first_row + height - 1 of a taller image of `whole_height`
/// rows: a piece of a .pvti, its extent saying where it lies in the whole image.
void write_image_data_piece(const std::filesystem::path& path, int width, int height, int first_row,
                            int whole_height, const std::vector<DataField>& point_fields);

} // namespace texsim::io
