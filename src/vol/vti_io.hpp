#pragma once
/// Dense grids to and from VTK XML image data (.vti): one point-data array of float32, one
/// component for scalar grids and three for colour grids; spacing and origin are the image's.
#include "vol/dense_grid.hpp"

#include <filesystem>
#include <string>

namespace texsim::vol {

/// Writes `grid` as a .vti file with one point-data array `array_name` (binary, zlib-compressed,
/// values bit-exact), atomically (core/atomic_output.hpp). Throws Error naming the file if it
/// cannot be written, leaving a file already at `path` as it was.
void write_vti(const std::filesystem::path& path, const ScalarGrid& grid,
               const std::string& array_name);
void write_vti(const std::filesystem::path& path, const RgbGrid& grid,
               const std::string& array_name);

/// Reads the point-data array `array_name` (or, if empty, the first one) of a .vti file: one
/// component -> ScalarGrid, three -> RgbGrid, any numeric type converted to float. Throws
/// InputError naming the file if it is missing or unreadable, has no such array (the message lists
/// the arrays it has), or the array has another number of components.
AnyGrid read_vti(const std::filesystem::path& path, const std::string& array_name = "");

} // namespace texsim::vol
