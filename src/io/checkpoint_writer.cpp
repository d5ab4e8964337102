#include "io/checkpoint_writer.hpp"

#include "core/atomic_output.hpp"
#include "io/checkpoint_format.hpp"
#include "io/hdf5_file.hpp"
#include "io/hdf5_scalar_type.hpp"
#include "par/collective.hpp"
#include "par/hdf5_call.hpp"
#include "par/parallel_file.hpp"
#include "par/positional_checksum.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace texsim::io {
namespace {

/// What each rank declares about its block of a dataset, gathered to check the tiling.
struct BlockDeclaration {
  std::uint64_t offset;
  std::uint64_t count;
  std::uint64_t global_count;
  std::uint64_t components;
};

void verify_blocks_tile(const std::string& name, std::vector<BlockDeclaration> blocks) {
  for (const auto& block : blocks)
    TEXSIM_VERIFY(block.global_count == blocks.front().global_count &&
                      block.components == blocks.front().components,
                  "checkpoint dataset '" << name
                                         << "': ranks disagree on its global count or components");
  std::sort(blocks.begin(), blocks.end(),
            [](const auto& a, const auto& b) { return a.offset < b.offset; });
  std::uint64_t next = 0;
  for (const auto& block : blocks) {
    if (block.count == 0)
      continue;
    TEXSIM_VERIFY(block.offset == next,
                  "checkpoint dataset '" << name << "': rank blocks do not tile [0, "
                                         << blocks.front().global_count << "): a block starts at "
                                         << block.offset << " where " << next << " was expected");
    next += block.count;
  }
  TEXSIM_VERIFY(next == blocks.front().global_count, "checkpoint dataset '"
                                                         << name << "': rank blocks cover [0, "
                                                         << next << ") instead of [0, "
                                                         << blocks.front().global_count << ")");
}

} // namespace

CheckpointWriter::CheckpointWriter(const par::Comm& comm, std::filesystem::path directory,
                                   const std::string& config_hash, std::int64_t step, int keep_last)
    : comm_(comm), directory_(std::move(directory)),
      temporary_path_(par::shared_temporary_path(comm, directory_ / checkpoint_file_name(step))),
      step_(step), keep_last_(keep_last) {
  par::run_collectively(comm_, [&] {
    file_ = create_parallel_file(comm_, temporary_path_);
    write_attribute(file_.get(), format_version_attribute, checkpoint_format_version,
                    temporary_path_);
    write_attribute(file_.get(), config_hash_attribute, config_hash, temporary_path_);
    write_attribute(file_.get(), step_attribute, step_, temporary_path_);
  });
}

void CheckpointWriter::write_block(const std::string& name, ScalarType type, const void* data,
                                   std::size_t local_scalars, std::uint64_t global_offset,
                                   std::uint64_t global_count, int components) {
  const std::uint64_t local_count = components > 0 ? local_scalars / components : 0;
  par::run_collectively(comm_, [&] {
    TEXSIM_VERIFY(file_, temporary_path_.string() << ": write after commit");
    TEXSIM_VERIFY(!name.empty() && !written_.contains(name),
                  temporary_path_.string()
                      << ": dataset name '" << name << "' is empty or already written");
    TEXSIM_VERIFY(components >= 1 && local_scalars % components == 0,
                  "checkpoint dataset '" << name << "': " << local_scalars
                                         << " local values are not a multiple of " << components
                                         << " components");
    TEXSIM_VERIFY(global_offset + local_count <= global_count,
                  "checkpoint dataset '" << name << "': local block [" << global_offset << ", "
                                         << global_offset + local_count << ") exceeds "
                                         << global_count << " elements");
  });
  const BlockDeclaration mine{global_offset, local_count, global_count,
                              static_cast<std::uint64_t>(components)};
  std::vector<BlockDeclaration> all(comm_.size);
  MPI_Allgather(&mine, 4, MPI_UINT64_T, all.data(), 4, MPI_UINT64_T, comm_.raw);
  par::run_collectively(comm_, [&] { verify_blocks_tile(name, all); });

  const std::uint64_t local_checksum =
      par::checksum_block(data, local_scalars, scalar_size(type), global_offset * components);
  const std::uint64_t checksum = par::checksum_sum_over_ranks(comm_, local_checksum);

  par::run_collectively(comm_, [&] {
    const auto& file = temporary_path_;
    const int rank = components == 1 ? 1 : 2;
    const std::array<hsize_t, 2> dims{global_count, static_cast<hsize_t>(components)};
    const par::Hdf5Handle file_space(
        TEXSIM_HDF5_CALL(H5Screate_simple(rank, dims.data(), nullptr), file.string()), H5Sclose);
    const par::Hdf5Handle create(TEXSIM_HDF5_CALL(H5Pcreate(H5P_DATASET_CREATE), file.string()),
                                 H5Pclose);
    TEXSIM_HDF5_CALL(H5Pset_fill_time(create.get(), H5D_FILL_TIME_NEVER), file.string());
    // No creation/modification times in the object header: the same state, the same bytes.
    TEXSIM_HDF5_CALL(H5Pset_obj_track_times(create.get(), false), file.string());
    const par::Hdf5Handle dataset(
        TEXSIM_HDF5_CALL(H5Dcreate2(file_.get(), name.c_str(), native_hdf5_type(type),
                                    file_space.get(), H5P_DEFAULT, create.get(), H5P_DEFAULT),
                         file.string()),
        H5Dclose);
    const std::array<hsize_t, 2> start{global_offset, 0};
    const std::array<hsize_t, 2> count{local_count, static_cast<hsize_t>(components)};
    const std::array<hsize_t, 2> memory_dims{std::max<hsize_t>(local_count, 1), count[1]};
    const par::Hdf5Handle memory_space(
        TEXSIM_HDF5_CALL(H5Screate_simple(rank, memory_dims.data(), nullptr), file.string()),
        H5Sclose);
    if (local_count == 0) {
      TEXSIM_HDF5_CALL(H5Sselect_none(file_space.get()), file.string());
      TEXSIM_HDF5_CALL(H5Sselect_none(memory_space.get()), file.string());
    } else {
      TEXSIM_HDF5_CALL(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr,
                                           count.data(), nullptr),
                       file.string());
    }
    const par::Hdf5Handle transfer(TEXSIM_HDF5_CALL(H5Pcreate(H5P_DATASET_XFER), file.string()),
                                   H5Pclose);
    TEXSIM_HDF5_CALL(H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_COLLECTIVE), file.string());
    TEXSIM_HDF5_CALL(H5Dwrite(dataset.get(), native_hdf5_type(type), memory_space.get(),
                              file_space.get(), transfer.get(), data),
                     file.string());
    write_attribute(dataset.get(), checksum_attribute, checksum, file);
  });
  written_.insert(name);
}

void CheckpointWriter::store_attribute(const std::string& name, const AttributeValue& value) {
  par::run_collectively(comm_, [&] {
    TEXSIM_VERIFY(file_, temporary_path_.string() << ": attribute set after commit");
    TEXSIM_VERIFY(!name.starts_with("texsim_"),
                  "checkpoint attribute name '" << name << "' is reserved (texsim_ prefix)");
    write_attribute(file_.get(), name, value, temporary_path_);
  });
}

void CheckpointWriter::set_attribute(const std::string& name, std::int64_t value) {
  store_attribute(name, value);
}
void CheckpointWriter::set_attribute(const std::string& name, std::uint64_t value) {
  store_attribute(name, value);
}
void CheckpointWriter::set_attribute(const std::string& name, double value) {
  store_attribute(name, value);
}
void CheckpointWriter::set_attribute(const std::string& name, const std::string& value) {
  store_attribute(name, value);
}

std::filesystem::path CheckpointWriter::commit() {
  const auto final_path = directory_ / checkpoint_file_name(step_);
  par::run_collectively(comm_, [&] {
    TEXSIM_VERIFY(file_, temporary_path_.string() << ": committed twice");
    // Every rank's writes reach the disk (MPI_File_sync) before rank 0 renames the file.
    TEXSIM_HDF5_CALL(H5Fflush(file_.get(), H5F_SCOPE_GLOBAL), temporary_path_.string());
    TEXSIM_HDF5_CALL(file_.reset(), temporary_path_.string());
  });
  par::run_collectively(comm_, [&] {
    if (!comm_.is_root())
      return;
    commit_temporary(temporary_path_, final_path);
    std::vector<std::int64_t> kept;
    for (const std::int64_t step : list_checkpoint_steps(directory_)) {
      if (step > step_)
        std::filesystem::remove(directory_ / checkpoint_file_name(step));
      else
        kept.push_back(step);
    }
    const auto keep = static_cast<std::size_t>(keep_last_);
    for (std::size_t i = 0; i + keep < kept.size(); ++i)
      std::filesystem::remove(directory_ / checkpoint_file_name(kept[i]));
  });
  return final_path;
}

} // namespace texsim::io
