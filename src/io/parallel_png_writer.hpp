#pragma once
/// A PNG image whose rows are spread over ranks, written without gathering its pixels: every rank
/// filters and deflates its own rows (zlib), and only the compressed bytes travel to the rank that
/// writes the file. libpng (and VTK's writer on top of it) wants the whole image in one process,
/// which for a 6144^2 atlas means 113 MB of pixels gathered and compressed on one core; the PNG
/// container itself is a few chunks (signature, IHDR, IDAT, IEND) and is written here.
///
/// The zlib stream is cut into segments, each deflated on its own and ended by a sync flush (the
/// last by a finish), their Adler-32 sums combined on the writing rank. Segments end at every
/// multiple of `segment_rows` and at each rank's last row, so the file's bytes depend on the image
/// and segment_rows only, whatever the ranks, as long as every rank's rows start at a multiple of
/// segment_rows. Each row is filtered as the PNG specification recommends: of its five filters,
/// the one whose output has the least sum of absolute values (as signed bytes).
#include "par/comm.hpp"

#include <cstdint>
#include <filesystem>
#include <span>

namespace texsim::io {

/// What a pixel holds.
enum class PngPixels {
  rgb8,  ///< 3 bytes: red, green, blue
  grey16 ///< 2 bytes: one 16-bit value, most significant byte first (as PNG stores it)
};

/// This rank's rows first_row .. first_row + count - 1 of the image, as PNG stores them (row
/// after row, top row first), and the row above them, which the filters look at (empty when
/// first_row is 0).
struct PngRows {
  int first_row = 0;
  int count = 0;
  std::span<const std::uint8_t> pixels;
  std::span<const std::uint8_t> above;
};

/// Writes a width x height PNG to `path` on `root`, atomically (core/atomic_output.hpp). The
/// ranks' rows, in rank order, must be rows 0 .. height - 1 each once (a rank may hold none).
/// Collective; a failure on any rank (rows that do not fit, an unwritable file) is raised as the
/// same texsim::Error, naming the file, on every rank.
void write_parallel_png(const par::Comm& comm, const std::filesystem::path& path, int width,
                        int height, PngPixels pixels, const PngRows& rows, int segment_rows,
                        int root = 0);

} // namespace texsim::io
