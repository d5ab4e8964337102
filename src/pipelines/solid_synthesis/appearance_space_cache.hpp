#pragma once
/// Appearance spaces kept between runs (Su 2008, section 3.1: the transformed exemplar is computed
/// once and reused): the stack, its neighbourhood statistics and the PCA projection depend only on
/// the exemplar and the appearance options, so a run stores them in an HDF5 file under a key naming
/// both and later runs with the same key read them back, bit for bit.
///
/// File layout (format version 1), every dataset chunked per index of its first axis and
/// Fletcher-32 checksummed so damaged data is noticed:
///   root attributes "format_version", "key", "periodic", "levels"; dataset "colours", float32,
///   shape [nz, ny, nx, C];
///   group "level_<s>" per stack level: attributes "spacing", "window", "retained_variance";
///   datasets "stack" (float32 [nz, ny, nx, C]), "features" (float32 [nz, ny, nx, d]), "mean"
///   (float64 [window^3 C]) and "basis" (float64 [d, window^3 C]: row j is column j of the matrix).
/// Written under a temporary name and renamed, so a reader never sees half a file.
#include "par/comm.hpp"
#include "pipelines/solid_synthesis/appearance_space.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace texsim::pipelines::solid_synthesis {

/// "<exemplar hash>-d<dimensions>-w<window>-<toroidal|discard>": the exemplar's content hash
/// (Exemplar::content_hash, 16 hex digits) and the options. Usable as part of a file name. Throws
/// Error if the hash is not 16 lower-case hex digits. Not collective.
std::string appearance_cache_key(const std::string& exemplar_hash,
                                 const AppearanceOptions& options);

/// The appearance space stored in `file` if it exists, is intact and holds `key`; nothing otherwise
/// (the caller rebuilds and overwrites). Rank 0 reads, every rank gets the result. Collective.
std::optional<AppearanceSpace> load_appearance_space(const par::Comm& comm,
                                                     const std::filesystem::path& file,
                                                     const std::string& key);

/// Stores `space` under `key` (from appearance_cache_key) in `file`, creating its directory and
/// replacing any older file atomically. Rank 0 writes; a failure to write is a warning, not an
/// error (the run has its space, only the next run loses the cache). Throws Error if `space` does
/// not have the dimensions, window and border the key names. Collective.
void save_appearance_space(const par::Comm& comm, const std::filesystem::path& file,
                           const std::string& key, const AppearanceSpace& space);

} // namespace texsim::pipelines::solid_synthesis
