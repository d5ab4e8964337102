#pragma once
/// Dense grids to and from VTK XML image data (.vti): one point-data array of float32, one
/// component for scalar grids and three for colour grids; spacing and origin are the image's.
#include "vol/dense_grid.hpp"

#include <filesystem>
#include <string>

namespace texsim::vol {

/// Writes `grid` as a .vti file with one point-data array `array_name` (binary, zlib-compressed,
/// values bit-exact), atomically (core/atomic_output.hpp). Throws Error naming the file if it
/// cannot be written, leaving a file already at `path` as it was. With `z_first` > 0 the grid is
/// planes z_first.. of a larger image (its extent starts there; spacing and origin are the
/// whole image's): a piece of a .pvti (parallel_vti_writer.hpp).
void write_vti(const std::filesystem::path& path, const ScalarGrid& grid,
               const std::string& array_name, int z_first = 0);
void write_vti(const std::filesystem::path& path, const RgbGrid& grid,
               const std::string& array_name, int z_first = 0);

/// Reads the point-data array `array_name` (or, if empty, the first one) of a .vti file, or of the
/// pieces of a .pvti file assembled into one grid: one
/// component -> ScalarGrid, three -> RgbGrid, any numeric type converted to float. Throws
/// InputError naming the file if it is missing or unreadable, has no such array (the message lists
/// the arrays it has), or the array has another number of components.
AnyGrid read_vti(const std::filesystem::path& path, const std::string& array_name = "");

} // namespace texsim::vol
