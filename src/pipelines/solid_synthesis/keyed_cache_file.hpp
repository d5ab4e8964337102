#pragma once
/// Cache files of precomputed results (appearance spaces, similarity sets): one HDF5 file per
/// key, whose root attributes hold a format version and the key. Files are written atomically
/// (core/atomic_output.hpp), so a reader never sees half a file.
#include "par/hdf5_handle.hpp"

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace texsim::pipelines::solid_synthesis {

/// `file` opened for reading when it exists, is HDF5 and carries `format_version` and `key`;
/// nothing otherwise. May throw for a damaged file (callers count any exception as a miss). Not
/// collective.
std::optional<par::Hdf5Handle> open_cache_file(const std::filesystem::path& file,
                                               const std::string& key, std::int64_t format_version);

/// Creates a temporary file, lets `fill(h5, file)` store the payload (`file` is for messages),
/// adds the format version and key, and commits it over `file` (fsync, rename); on failure the
/// temporary is removed and the exception passed on. Not collective.
void write_cache_file(const std::filesystem::path& file, const std::string& key,
                      std::int64_t format_version,
                      const std::function<void(hid_t, const std::filesystem::path&)>& fill);

} // namespace texsim::pipelines::solid_synthesis
