#pragma once
/// A 2D image spread over ranks, written as ParaView writes images in parallel: the image is cut
/// into strips of a fixed number of rows, each written as a .vti piece by the rank that holds it,
/// under a .pvti that lists them all; ParaView opens the .pvti as one image. The strips depend on
/// the image only, not on the ranks, so any rank count writes the same files.
#include "io/surface_piece.hpp"
#include "par/comm.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace texsim::io {

/// This rank's strips first_strip .. first_strip + count - 1 (count 0: none) of an image cut
/// into strips of strip_rows rows, row 0 at the top. Strip s covers rows s * strip_rows ..
/// min((s + 1) * strip_rows, height - 1): one row more than it owns, shared with the next strip,
/// because VTK's point data pieces share their boundary points (otherwise ParaView draws a gap).
/// `point_fields` hold the rows of all this rank's strips, shared rows once, row-major; every
/// rank gives the same names, types and components (with empty values when it has no strip).
struct ImageStrips {
  int first_strip = 0;
  int count = 0;
  std::vector<DataField> point_fields;
};

/// Writes this rank's strips to <dir>/<basename>/<basename>_<strip>.vti and, on rank 0,
/// <dir>/<basename>.pvti; returns the .pvti's path on every rank. Every strip of the image must be
/// held by one rank. Files are written atomically (core/atomic_output.hpp). Collective; a failure
/// on any rank is raised as the same texsim::Error, naming the file, on every rank.
std::filesystem::path write_parallel_image_data(const par::Comm& comm,
                                                const std::filesystem::path& dir,
                                                const std::string& basename, int width, int height,
                                                int strip_rows, const ImageStrips& strips);

} // namespace texsim::io
