#pragma once
/// Opening HDF5 files: in parallel through MPI-IO (checkpoint writes and reads), or serially on
/// one rank for a quick look at a file's attributes.
#include "par/comm.hpp"
#include "par/hdf5_handle.hpp"

#include <filesystem>

namespace texsim::io {

/// Creates (truncating) `path` for parallel writing with the MPI-IO driver. Collective.
par::Hdf5Handle create_parallel_file(const par::Comm& comm, const std::filesystem::path& path);

/// Opens `path` read-only with the MPI-IO driver. Collective.
par::Hdf5Handle open_parallel_file(const par::Comm& comm, const std::filesystem::path& path);

/// Opens `path` read-only with the default (POSIX) driver. Not collective.
par::Hdf5Handle open_serial_file(const std::filesystem::path& path);

} // namespace texsim::io
