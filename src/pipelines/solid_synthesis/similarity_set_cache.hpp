#pragma once
/// Similarity sets kept between runs: they cost about 2 d N^2 flops (minutes for a 64^3 exemplar,
/// hours at 256^3) and depend only on the features and the options, so a run stores them in an
/// HDF5 file under a key naming both and later runs with the same key read them back.
///
/// File layout (format version 1): dataset "candidates", int32, shape [nz, ny, nx, k]
/// (candidates[v * k + i] as in SimilaritySets); root attributes "format_version", "key", "k",
/// "window", "periodic". Written under a temporary name and renamed, so a reader never sees half a
/// file.
#include "par/comm.hpp"
#include "pipelines/solid_synthesis/similarity_sets.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace texsim::pipelines::solid_synthesis {

/// "<nx>x<ny>x<nz>x<d>-k<k>-n<window>-<torus|open>-<16 hex digits>": the grid, the options and a
/// hash of the feature bytes. Usable as part of a file name. Not collective.
std::string similarity_cache_key(const vol::ChannelGrid& features,
                                 const SimilarityOptions& options);

/// The sets stored in `file` if it exists, is intact and holds `key`; nothing otherwise (the caller
/// recomputes and overwrites). Rank 0 reads, every rank gets the result. Collective.
std::optional<SimilaritySets> load_similarity_sets(const par::Comm& comm,
                                                   const std::filesystem::path& file,
                                                   const std::string& key);

/// Stores `sets` under `key` (from similarity_cache_key) in `file`, creating its directory and
/// replacing any older file atomically. Rank 0 writes; a failure to write is a warning, not an
/// error (the run has its sets, only the next run loses the cache). Collective.
void save_similarity_sets(const par::Comm& comm, const std::filesystem::path& file,
                          const std::string& key, const SimilaritySets& sets);

} // namespace texsim::pipelines::solid_synthesis
