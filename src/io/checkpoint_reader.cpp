#include "io/checkpoint_reader.hpp"

#include "io/checkpoint_format.hpp"
#include "io/hdf5_file.hpp"
#include "io/hdf5_scalar_type.hpp"
#include "par/collective.hpp"
#include "par/hdf5_call.hpp"
#include "par/positional_checksum.hpp"

#include <algorithm>
#include <array>
#include <functional>
#include <vector>

namespace texsim::io {
namespace {

/// Scalars read at a time while verifying checksums, to bound memory on huge datasets.
constexpr std::uint64_t verify_chunk_scalars = std::uint64_t{1} << 21;

/// Runs `work`; any failure that is not already an InputError means the file is damaged (HDF5
/// could not read what a complete checkpoint holds), reported as an InputError naming the file.
void as_corrupt_on_failure(const std::filesystem::path& path, const std::function<void()>& work) {
  try {
    work();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    TEXSIM_INPUT_ERROR(path.string() << ": corrupt checkpoint (" << e.what() << ")");
  }
}

template <class T> const char* scalar_or_string_name() {
  if constexpr (std::is_same_v<T, std::string>)
    return "a string";
  else
    return scalar_type_name(scalar_type_of<T>());
}

template <class T>
T expect_attribute(const AttributeValue& value, const std::filesystem::path& path,
                   const std::string& name, const char* expected) {
  if (const auto* v = std::get_if<T>(&value))
    return *v;
  TEXSIM_INPUT_ERROR(path.string()
                     << ": checkpoint attribute '" << name << "' is not " << expected);
}

/// Selects elements [offset, offset + count) of a dataset of `components` scalars per element.
void select_elements(hid_t space, std::uint64_t offset, std::uint64_t count, int components,
                     const std::filesystem::path& path) {
  if (count == 0) {
    TEXSIM_HDF5_CALL(H5Sselect_none(space), path.string());
    return;
  }
  const std::array<hsize_t, 2> start{offset, 0};
  const std::array<hsize_t, 2> size{count, static_cast<hsize_t>(components)};
  TEXSIM_HDF5_CALL(
      H5Sselect_hyperslab(space, H5S_SELECT_SET, start.data(), nullptr, size.data(), nullptr),
      path.string());
}

par::Hdf5Handle memory_space(std::uint64_t count, int components,
                             const std::filesystem::path& path) {
  const std::array<hsize_t, 2> dims{std::max<hsize_t>(count, 1), static_cast<hsize_t>(components)};
  par::Hdf5Handle space(
      TEXSIM_HDF5_CALL(H5Screate_simple(components == 1 ? 1 : 2, dims.data(), nullptr),
                       path.string()),
      H5Sclose);
  if (count == 0)
    TEXSIM_HDF5_CALL(H5Sselect_none(space.get()), path.string());
  return space;
}

} // namespace

CheckpointReader::CheckpointReader(const par::Comm& comm, std::filesystem::path path,
                                   const std::string& config_hash)
    : comm_(comm), path_(std::move(path)) {
  par::run_collectively(comm_, [&] {
    if (comm_.is_root() && !std::filesystem::is_regular_file(path_))
      TEXSIM_INPUT_ERROR(path_.string() << ": no such checkpoint file");
  });
  par::run_collectively(comm_, [&] { open_and_check_header(config_hash); });
  verify_checksums();
}

void CheckpointReader::open_and_check_header(const std::string& config_hash) {
  as_corrupt_on_failure(path_, [&] { file_ = open_parallel_file(comm_, path_); });
  if (!has_attribute_here(format_version_attribute))
    TEXSIM_INPUT_ERROR(path_.string() << ": not a texsim checkpoint (no "
                                      << format_version_attribute << " attribute)");
  const std::int64_t version = expect_attribute<std::int64_t>(
      attribute_here(format_version_attribute), path_, format_version_attribute, "an int64");
  if (version != checkpoint_format_version)
    TEXSIM_INPUT_ERROR(path_.string()
                       << ": checkpoint format version " << version << ", this build reads version "
                       << checkpoint_format_version);
  const std::string stored_hash = expect_attribute<std::string>(
      attribute_here(config_hash_attribute), path_, config_hash_attribute, "a string");
  if (stored_hash != config_hash)
    TEXSIM_INPUT_ERROR(path_.string() << ": written by a different configuration (config hash "
                                      << stored_hash << ", this run " << config_hash
                                      << "); start a fresh output.dir or use the matching config");
  step_ = expect_attribute<std::int64_t>(attribute_here(step_attribute), path_, step_attribute,
                                         "an int64");

  as_corrupt_on_failure(path_, [&] {
    H5G_info_t group{};
    TEXSIM_HDF5_CALL(H5Gget_info(file_.get(), &group), path_.string());
    for (hsize_t i = 0; i < group.nlinks; ++i) {
      const auto length =
          TEXSIM_HDF5_CALL(H5Lget_name_by_idx(file_.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i,
                                              nullptr, 0, H5P_DEFAULT),
                           path_.string());
      std::string name(static_cast<std::size_t>(length) + 1, '\0');
      TEXSIM_HDF5_CALL(H5Lget_name_by_idx(file_.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i,
                                          name.data(), name.size(), H5P_DEFAULT),
                       path_.string());
      name.resize(static_cast<std::size_t>(length));
      const par::Hdf5Handle dataset(
          TEXSIM_HDF5_CALL(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), path_.string()),
          H5Dclose);
      const par::Hdf5Handle type(TEXSIM_HDF5_CALL(H5Dget_type(dataset.get()), path_.string()),
                                 H5Tclose);
      const auto scalar = scalar_type_of_hdf5(type.get());
      TEXSIM_VERIFY(scalar, "dataset '" << name << "' has an unsupported element type");
      const par::Hdf5Handle space(TEXSIM_HDF5_CALL(H5Dget_space(dataset.get()), path_.string()),
                                  H5Sclose);
      const int rank = TEXSIM_HDF5_CALL(H5Sget_simple_extent_ndims(space.get()), path_.string());
      TEXSIM_VERIFY(rank == 1 || rank == 2, "dataset '" << name << "' has rank " << rank);
      std::array<hsize_t, 2> dims{0, 1};
      TEXSIM_HDF5_CALL(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr),
                       path_.string());
      const auto checksum = read_attribute(dataset.get(), checksum_attribute, path_);
      TEXSIM_VERIFY(std::holds_alternative<std::uint64_t>(checksum),
                    "dataset '" << name << "' has no valid checksum");
      datasets_[name] = DatasetInfo{*scalar, dims[0], static_cast<int>(dims[1]),
                                    std::get<std::uint64_t>(checksum)};
    }
  });
}

std::uint64_t CheckpointReader::local_checksum_share(const std::string& name,
                                                     const DatasetInfo& info) const {
  const std::uint64_t begin = info.global_count * comm_.rank / comm_.size;
  const std::uint64_t end = info.global_count * (comm_.rank + 1) / comm_.size;
  const std::uint64_t chunk = std::max<std::uint64_t>(1, verify_chunk_scalars / info.components);
  const std::size_t element_bytes = scalar_size(info.type) * info.components;
  std::vector<unsigned char> buffer(std::min(chunk, end - begin) * element_bytes);
  const par::Hdf5Handle dataset(
      TEXSIM_HDF5_CALL(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), path_.string()), H5Dclose);
  const par::Hdf5Handle file_space(TEXSIM_HDF5_CALL(H5Dget_space(dataset.get()), path_.string()),
                                   H5Sclose);
  std::uint64_t sum = 0;
  for (std::uint64_t first = begin; first < end; first += chunk) {
    const std::uint64_t count = std::min(chunk, end - first);
    select_elements(file_space.get(), first, count, info.components, path_);
    const par::Hdf5Handle memory = memory_space(count, info.components, path_);
    TEXSIM_HDF5_CALL(H5Dread(dataset.get(), native_hdf5_type(info.type), memory.get(),
                             file_space.get(), H5P_DEFAULT, buffer.data()),
                     path_.string());
    sum += par::checksum_block(buffer.data(), count * info.components, scalar_size(info.type),
                               first * info.components);
  }
  return sum;
}

void CheckpointReader::verify_checksums() {
  std::vector<std::uint64_t> local;
  par::run_collectively(comm_, [&] {
    as_corrupt_on_failure(path_, [&] {
      for (const auto& [name, info] : datasets_)
        local.push_back(local_checksum_share(name, info));
    });
  });
  std::vector<std::uint64_t> total(local.size());
  MPI_Allreduce(local.data(), total.data(), static_cast<int>(local.size()), MPI_UINT64_T, MPI_SUM,
                comm_.raw);
  par::run_collectively(comm_, [&] {
    std::size_t i = 0;
    for (const auto& [name, info] : datasets_) {
      if (total[i] != info.stored_checksum)
        TEXSIM_INPUT_ERROR(path_.string()
                           << ": corrupt checkpoint (dataset '" << name << "' has checksum "
                           << total[i] << ", " << info.stored_checksum << " was stored)");
      ++i;
    }
  });
}

std::vector<std::string> CheckpointReader::dataset_names() const {
  std::vector<std::string> names;
  for (const auto& entry : datasets_)
    names.push_back(entry.first);
  return names;
}

const CheckpointReader::DatasetInfo& CheckpointReader::info(const std::string& name) const {
  const auto found = datasets_.find(name);
  if (found == datasets_.end())
    TEXSIM_INPUT_ERROR(path_.string() << ": checkpoint has no dataset '" << name << "'");
  return found->second;
}

std::uint64_t CheckpointReader::global_count(const std::string& name) const {
  return info(name).global_count;
}
int CheckpointReader::components(const std::string& name) const {
  return info(name).components;
}
ScalarType CheckpointReader::type(const std::string& name) const {
  return info(name).type;
}

void CheckpointReader::read_block(const std::string& name, ScalarType type, void* data,
                                  std::size_t local_scalars, std::uint64_t global_offset,
                                  std::uint64_t count) const {
  par::run_collectively(comm_, [&] {
    const DatasetInfo& stored = info(name);
    TEXSIM_VERIFY(stored.type == type, path_.string() << ": dataset '" << name << "' holds "
                                                      << scalar_type_name(stored.type)
                                                      << ", read as " << scalar_type_name(type));
    TEXSIM_VERIFY(
        global_offset + count <= stored.global_count && local_scalars == count * stored.components,
        path_.string() << ": dataset '" << name << "' of " << stored.global_count << " elements x "
                       << stored.components << ": cannot read elements [" << global_offset << ", "
                       << global_offset + count << ") into " << local_scalars << " values");
  });
  const DatasetInfo& stored = info(name);
  par::run_collectively(comm_, [&] {
    const par::Hdf5Handle dataset(
        TEXSIM_HDF5_CALL(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), path_.string()),
        H5Dclose);
    const par::Hdf5Handle file_space(TEXSIM_HDF5_CALL(H5Dget_space(dataset.get()), path_.string()),
                                     H5Sclose);
    select_elements(file_space.get(), global_offset, count, stored.components, path_);
    const par::Hdf5Handle memory = memory_space(count, stored.components, path_);
    const par::Hdf5Handle transfer(TEXSIM_HDF5_CALL(H5Pcreate(H5P_DATASET_XFER), path_.string()),
                                   H5Pclose);
    TEXSIM_HDF5_CALL(H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_COLLECTIVE), path_.string());
    TEXSIM_HDF5_CALL(H5Dread(dataset.get(), native_hdf5_type(type), memory.get(), file_space.get(),
                             transfer.get(), data),
                     path_.string());
  });
}

AttributeValue CheckpointReader::attribute_here(const std::string& name) const {
  if (!has_attribute_here(name))
    TEXSIM_INPUT_ERROR(path_.string() << ": checkpoint has no attribute '" << name << "'");
  AttributeValue value;
  as_corrupt_on_failure(path_, [&] { value = read_attribute(file_.get(), name, path_); });
  return value;
}

bool CheckpointReader::has_attribute_here(const std::string& name) const {
  bool found = false;
  as_corrupt_on_failure(path_, [&] { found = io::has_attribute(file_.get(), name, path_); });
  return found;
}

template <class T> T CheckpointReader::collective_attribute(const std::string& name) const {
  T value{};
  par::run_collectively(comm_, [&] {
    value = expect_attribute<T>(attribute_here(name), path_, name, scalar_or_string_name<T>());
  });
  return value;
}

bool CheckpointReader::has_attribute(const std::string& name) const {
  bool found = false;
  par::run_collectively(comm_, [&] { found = has_attribute_here(name); });
  return found;
}
std::int64_t CheckpointReader::attribute_int64(const std::string& name) const {
  return collective_attribute<std::int64_t>(name);
}
std::uint64_t CheckpointReader::attribute_uint64(const std::string& name) const {
  return collective_attribute<std::uint64_t>(name);
}
double CheckpointReader::attribute_double(const std::string& name) const {
  return collective_attribute<double>(name);
}
std::string CheckpointReader::attribute_string(const std::string& name) const {
  return collective_attribute<std::string>(name);
}

} // namespace texsim::io
