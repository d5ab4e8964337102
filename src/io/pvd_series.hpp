#pragma once
/// A ParaView time series (.pvd collection) kept up to date while a run goes on: every add()
/// rewrites the file atomically, so ParaView can open a running job's output at any moment.
/// Only rank 0 touches the file; every rank holds the same entries.
#include "par/comm.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace texsim::io {

/// "step_000000042": the name of step 42's files in a series (zero-padded, so they sort by step).
std::string step_name(std::int64_t step);

class PvdSeries {
public:
  struct Entry {
    double time;
    int part;
    std::string file; ///< relative to the .pvd's directory, as written in the collection
  };

  /// Starts an empty series at `path` and writes it (replacing any file there). Collective.
  PvdSeries(const par::Comm& comm, std::filesystem::path path);

  /// Continues the series at `path` after a restart from `restart_time`: entries with time
  /// <= restart_time are kept, later ones (to be rewritten by the restarted run) are dropped and
  /// the file is rewritten. A missing file gives an empty series; a malformed one is an InputError
  /// naming it. Collective.
  static PvdSeries resume(const par::Comm& comm, std::filesystem::path path, double restart_time);

  /// Records `relative_file` (relative to the .pvd's directory) at `time` for `part` and rewrites
  /// the collection; an entry with the same time and part is replaced. Entries stay sorted by
  /// (time, part). Collective: call on every rank with the same arguments.
  void add(double time, const std::string& relative_file, int part = 0);

  /// The entries of the collection at `path`, in file order (a reader of simulator output
  /// series, not only of texsim's). Serial. InputError naming the file when it is missing,
  /// unreadable or malformed.
  static std::vector<Entry> read_entries(const std::filesystem::path& path);

  const std::vector<Entry>& entries() const { return entries_; }
  const std::filesystem::path& path() const { return path_; }

private:
  PvdSeries(const par::Comm& comm, std::filesystem::path path, std::vector<Entry> entries);
  void rewrite() const;

  par::Comm comm_;
  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

} // namespace texsim::io
