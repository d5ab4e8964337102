#pragma once
/// Dense grids to and from HDF5 files with the serial API (works on one rank of the parallel
/// build). Layout: a float32 dataset of shape [nz][ny][nx] for scalar grids or [nz][ny][nx][3]
/// for colour grids (C order, so x is fastest as in DenseGrid), with double[3] attributes
/// "spacing" and "origin" in x, y, z order.
#include "vol/dense_grid.hpp"

#include <filesystem>
#include <string>

namespace texsim::vol {

/// Writes `grid` as dataset `dataset` of a new HDF5 file, replacing any file at `path` atomically
/// (core/atomic_output.hpp). Not collective. Throws Error naming the file and dataset if an HDF5
/// call fails, leaving a file already at `path` as it was.
void write_hdf5_grid(const std::filesystem::path& path, const ScalarGrid& grid,
                     const std::string& dataset);
void write_hdf5_grid(const std::filesystem::path& path, const RgbGrid& grid,
                     const std::string& dataset);

/// Reads dataset `dataset` (or, if empty, the first dataset in the root group): rank 3 ->
/// ScalarGrid, rank 4 with last extent 3 -> RgbGrid; integer or float data converted to float;
/// missing spacing/origin attributes default to 1 and 0. Throws InputError naming the file (and
/// the dataset) if the file is missing or not HDF5, the dataset does not exist (the message lists
/// the root datasets), or its shape or type does not fit.
AnyGrid read_hdf5_grid(const std::filesystem::path& path, const std::string& dataset = "");

} // namespace texsim::vol
