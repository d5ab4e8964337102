#pragma once
/// One file that every rank writes its own parts of at once (MPI-IO), committed atomically: it is
/// written under rank 0's temporary name (core/atomic_output.hpp) and renamed over its final name
/// only after every rank's bytes are on disk, so a killed job never leaves half a file behind.
///
///   par::ParallelFile file(comm, dir / "result.vdb");      // collective
///   if (comm.is_root()) file.write_at(0, header);           // one rank alone
///   file.write_runs(my_runs);                               // collective, every rank's parts
///   file.commit();                                          // collective
#include "par/comm.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace texsim::par {

/// `path`'s temporary name for the processes of `comm`: rank 0's, the same on every rank.
/// Collective.
std::filesystem::path shared_temporary_path(const Comm& comm, const std::filesystem::path& path);

/// `bytes` to be written at byte `offset` of a file.
struct ByteRun {
  std::uint64_t offset = 0;
  std::span<const std::byte> bytes;
};

class ParallelFile {
public:
  /// Creates the temporary file of `path` on every rank. Collective; throws texsim::Error naming
  /// `path` on every rank if it cannot be created.
  ParallelFile(const Comm& comm, std::filesystem::path path);
  /// Removes the temporary file if the file was not committed. Collective, like MPI_File_close:
  /// the writers raise errors on every rank together (par::run_collectively), so every rank
  /// unwinds to here.
  ~ParallelFile();
  ParallelFile(const ParallelFile&) = delete;
  ParallelFile& operator=(const ParallelFile&) = delete;

  /// Writes `bytes` at `offset` from this rank alone; throws texsim::Error naming the file on
  /// this rank if that fails (callers run it inside par::run_collectively). Not collective.
  void write_at(std::uint64_t offset, std::span<const std::byte> bytes);
  /// Writes this rank's `runs` (sorted by offset, not overlapping each other or another rank's)
  /// in collective calls of at most 1 GiB per rank, so no count passes MPI's int. Collective;
  /// a rank may have no runs.
  void write_runs(std::span<const ByteRun> runs);
  /// Flushes every rank's writes to disk and renames the file over its final name. Collective.
  void commit();

private:
  void close();

  Comm comm_;
  std::filesystem::path path_;
  std::filesystem::path temporary_;
  MPI_File file_ = MPI_FILE_NULL;
  bool committed_ = false;
};

} // namespace texsim::par
