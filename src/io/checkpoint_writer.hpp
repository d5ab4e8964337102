#pragma once
/// Writing one checkpoint: named arrays split across ranks into one HDF5 file through MPI-IO,
/// checksummed, then flushed to disk and renamed into place by commit() (the same pattern as every
/// other output, core/atomic_output.hpp). Obtained from CheckpointStore::begin().
#include "io/hdf5_attribute.hpp"
#include "io/scalar_type.hpp"
#include "par/comm.hpp"
#include "par/hdf5_handle.hpp"

#include <concepts>
#include <cstdint>
#include <filesystem>
#include <set>
#include <span>
#include <string>

namespace texsim::io {

class CheckpointWriter {
public:
  /// Writes dataset `name` of `global_count` elements of `components` scalars each. This rank
  /// holds elements [global_offset, global_offset + local.size() / components); the blocks of all
  /// ranks must tile [0, global_count) exactly (a rank may hold none). Stores the dataset's
  /// rank-count-independent checksum with it. Collective; errors are raised on every rank.
  template <class T>
  void write(const std::string& name, std::span<const T> local, std::uint64_t global_offset,
             std::uint64_t global_count, int components = 1) {
    write_block(name, scalar_type_of<T>(), local.data(), local.size(), global_offset, global_count,
                components);
  }

  /// Stores a root attribute (RNG seed, simulated time, ...). Every rank passes the same value.
  /// Names starting with "texsim_" are reserved. Collective.
  void set_attribute(const std::string& name, std::int64_t value);
  void set_attribute(const std::string& name, std::uint64_t value);
  void set_attribute(const std::string& name, double value);
  void set_attribute(const std::string& name, const std::string& value);
  void set_attribute(const std::string& name, const char* value) {
    set_attribute(name, std::string(value));
  }
  template <std::integral I> void set_attribute(const std::string& name, I value) {
    if constexpr (std::is_signed_v<I>)
      set_attribute(name, static_cast<std::int64_t>(value));
    else
      set_attribute(name, static_cast<std::uint64_t>(value));
  }

  /// Flushes the file to disk (MPI_File_sync through H5Fflush), closes it, renames it to
  /// <dir>/step_<step>.h5 and flushes the directory (replacing a checkpoint of the same
  /// step of this run). Then removes checkpoints of later steps (left by a run that was killed and
  /// restarted from an earlier one: this run rewrites them) and all but the newest keep_last.
  /// Returns the final path. Collective. Without commit() the temporary file stays behind, is
  /// never read, and is removed by the next CheckpointStore opened on the directory.
  std::filesystem::path commit();

  std::int64_t step() const { return step_; }

  CheckpointWriter(CheckpointWriter&&) = default;
  CheckpointWriter& operator=(CheckpointWriter&&) = default;

private:
  friend class CheckpointStore;
  /// Creates <directory>/step_<step>.h5.tmp-<pid of rank 0> and stores the format version, config
  /// hash and step. Collective.
  CheckpointWriter(const par::Comm& comm, std::filesystem::path directory,
                   const std::string& config_hash, std::int64_t step, int keep_last);

  void write_block(const std::string& name, ScalarType type, const void* data,
                   std::size_t local_scalars, std::uint64_t global_offset,
                   std::uint64_t global_count, int components);
  void store_attribute(const std::string& name, const AttributeValue& value);

  par::Comm comm_;
  std::filesystem::path directory_;
  std::filesystem::path temporary_path_;
  std::int64_t step_ = 0;
  int keep_last_ = 1;
  std::set<std::string> written_;
  par::Hdf5Handle file_;
};

} // namespace texsim::io
