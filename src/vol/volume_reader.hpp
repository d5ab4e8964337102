#pragma once
/// One entry point for reading a volume exemplar from any supported file format.
#include "vol/dense_grid.hpp"

#include <filesystem>

namespace texsim::vol {

/// Reads .vdb (first FloatGrid/Vec3SGrid), .vti (first point array), .h5/.hdf5 (first root
/// dataset) or .inr by extension (case-insensitive). Colour grids are returned as stored; scalar
/// grids are rescaled linearly from [min, max] to [0, 1] (a constant grid becomes 0) and expanded
/// to grey. Throws InputError naming the file for an unknown extension or any reader's error.
RgbGrid read_volume(const std::filesystem::path& path);

/// The grey colour grid of a scalar grid rescaled from [min, max] to [0, 1]; spacing and origin
/// kept.
RgbGrid grey_from_scalar(const ScalarGrid& grid);

} // namespace texsim::vol
