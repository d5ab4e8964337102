#pragma once
/// Reading one verified checkpoint: obtained from CheckpointStore::open(), which has already
/// checked its format version, config hash and every dataset's checksum.
#include "io/hdf5_attribute.hpp"
#include "io/scalar_type.hpp"
#include "par/comm.hpp"
#include "par/hdf5_handle.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace texsim::io {

class CheckpointReader {
public:
  const std::filesystem::path& path() const { return path_; }
  std::int64_t step() const { return step_; }

  /// Names of the datasets, sorted.
  std::vector<std::string> dataset_names() const;
  bool has_dataset(const std::string& name) const { return datasets_.contains(name); }
  /// Number of elements, scalars per element and element type of a dataset; throws InputError
  /// naming the file if there is no such dataset. Not collective.
  std::uint64_t global_count(const std::string& name) const;
  int components(const std::string& name) const;
  ScalarType type(const std::string& name) const;

  /// Reads elements [global_offset, global_offset + count) of dataset `name` into `local`, which
  /// holds count * components(name) values; ranks may read any (overlapping) blocks. The element
  /// type must be the stored one. Collective; errors are raised on every rank.
  template <class T>
  void read(const std::string& name, std::span<T> local, std::uint64_t global_offset,
            std::uint64_t count) const {
    read_block(name, scalar_type_of<T>(), local.data(), local.size(), global_offset, count);
  }

  /// Root attributes set with CheckpointWriter::set_attribute. A missing attribute or one of
  /// another type is an InputError naming the file. Collective (every rank reads the same value).
  bool has_attribute(const std::string& name) const;
  std::int64_t attribute_int64(const std::string& name) const;
  std::uint64_t attribute_uint64(const std::string& name) const;
  double attribute_double(const std::string& name) const;
  std::string attribute_string(const std::string& name) const;

  CheckpointReader(CheckpointReader&&) = default;
  CheckpointReader& operator=(CheckpointReader&&) = default;

private:
  friend class CheckpointStore;
  /// Opens `path` with MPI-IO and verifies it against `config_hash` (see CheckpointStore::open).
  /// Collective.
  CheckpointReader(const par::Comm& comm, std::filesystem::path path,
                   const std::string& config_hash);

  struct DatasetInfo {
    ScalarType type;
    std::uint64_t global_count;
    int components;
    std::uint64_t stored_checksum;
  };

  void open_and_check_header(const std::string& config_hash);
  void verify_checksums();
  std::uint64_t local_checksum_share(const std::string& name, const DatasetInfo& info) const;
  const DatasetInfo& info(const std::string& name) const;
  void read_block(const std::string& name, ScalarType type, void* data, std::size_t local_scalars,
                  std::uint64_t global_offset, std::uint64_t count) const;
  /// Not collective: used inside the collective header check.
  AttributeValue attribute_here(const std::string& name) const;
  bool has_attribute_here(const std::string& name) const;
  template <class T> T collective_attribute(const std::string& name) const;

  par::Comm comm_;
  std::filesystem::path path_;
  std::int64_t step_ = 0;
  std::map<std::string, DatasetInfo> datasets_;
  par::Hdf5Handle file_;
};

} // namespace texsim::io
