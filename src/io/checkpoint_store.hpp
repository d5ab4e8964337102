#pragma once
/// The directory of a run's checkpoints: starting a new checkpoint, finding the newest usable one
/// on restart, and opening one with full verification.
///
///   CheckpointStore store(comm, out_dir / "checkpoints", config_hash, 3);
///   auto writer = store.begin(step);
///   writer.write<double>("u", local_u, first_row, total_rows);
///   writer.set_attribute("time", t);
///   writer.commit();
///   ...
///   const auto found = store.resolve("latest");  // found.skipped: damaged newer files
///   found.reader.read<double>("u", local_u, first_row, my_rows);
#include "core/error.hpp"
#include "io/checkpoint_reader.hpp"
#include "io/checkpoint_writer.hpp"
#include "par/comm.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace texsim::io {

/// A checkpoint that "latest" passed over, and why (the InputError message of opening it).
struct SkippedCheckpoint {
  std::filesystem::path path;
  std::string reason;
};

/// The checkpoint a restart spec resolved to, opened and verified (so it is read only once), with
/// the newer ones that were skipped (for rank 0 to report).
struct ResolvedCheckpoint {
  CheckpointReader reader;
  std::vector<SkippedCheckpoint> skipped;
};

class CheckpointStore {
public:
  /// Creates `directory` if needed. If it already holds checkpoints and the newest readable one
  /// was written with another config hash, throws InputError naming that file: a run never
  /// overwrites another configuration's checkpoints. Removes the temporary files of
  /// checkpoints a killed job left uncommitted. `keep_last` >= 1 checkpoints are kept.
  /// Collective; errors are raised on every rank.
  CheckpointStore(const par::Comm& comm, std::filesystem::path directory, std::string config_hash,
                  int keep_last);

  /// Starts writing the checkpoint of `step` under a temporary name. Collective.
  CheckpointWriter begin(std::int64_t step) const;

  /// Steps of the committed checkpoints in the directory, ascending, as seen by rank 0.
  /// Collective.
  std::vector<std::int64_t> steps() const;

  /// <directory>/step_<step>.h5.
  std::filesystem::path path_of(std::int64_t step) const;

  /// "latest": the newest checkpoint in the directory that opens and verifies (see open()); the
  /// newer ones that failed are listed in `skipped`. InputError if none is usable. Any other spec
  /// is a checkpoint file path, which must open and verify. Collective; reads every candidate
  /// checkpoint once in full.
  ResolvedCheckpoint resolve(const std::string& spec) const;

  /// resolve() for a restart: logs a warning (rank 0) for every newer checkpoint it skipped and
  /// returns the reader. Collective.
  CheckpointReader resolve_for_restart(const std::string& spec) const;

  /// Opens a checkpoint and verifies it: format version, config hash (a mismatch is an
  /// InputError "<file>: written by a different configuration ..."), and every dataset's checksum
  /// (a mismatch, a truncated or an unreadable file is an InputError "<file>: corrupt
  /// checkpoint ..."). Collective; errors are raised identically on every rank.
  CheckpointReader open(const std::filesystem::path& path) const;

  const std::filesystem::path& directory() const { return directory_; }
  const std::string& config_hash() const { return config_hash_; }

private:
  void refuse_other_configuration() const;

  par::Comm comm_;
  std::filesystem::path directory_;
  std::string config_hash_;
  int keep_last_;
};

} // namespace texsim::io
