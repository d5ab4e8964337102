#include "io/hdf5_file.hpp"

#include "par/hdf5_call.hpp"

namespace texsim::io {
namespace {

par::Hdf5Handle mpio_access_list(const par::Comm& comm, const std::filesystem::path& path) {
  par::Hdf5Handle access(TEXSIM_HDF5_CALL(H5Pcreate(H5P_FILE_ACCESS), path.string()), H5Pclose);
  TEXSIM_HDF5_CALL(H5Pset_fapl_mpio(access.get(), comm.raw, MPI_INFO_NULL), path.string());
  return access;
}

} // namespace

par::Hdf5Handle create_parallel_file(const par::Comm& comm, const std::filesystem::path& path) {
  par::silence_hdf5_error_printing();
  const par::Hdf5Handle access = mpio_access_list(comm, path);
  // The root group without creation/modification times: the same contents, the same bytes.
  const par::Hdf5Handle creation(TEXSIM_HDF5_CALL(H5Pcreate(H5P_FILE_CREATE), path.string()),
                                 H5Pclose);
  TEXSIM_HDF5_CALL(H5Pset_obj_track_times(creation.get(), false), path.string());
  return {TEXSIM_HDF5_CALL(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, creation.get(), access.get()),
                           path.string()),
          H5Fclose};
}

par::Hdf5Handle open_parallel_file(const par::Comm& comm, const std::filesystem::path& path) {
  par::silence_hdf5_error_printing();
  const par::Hdf5Handle access = mpio_access_list(comm, path);
  return {TEXSIM_HDF5_CALL(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get()), path.string()),
          H5Fclose};
}

par::Hdf5Handle open_serial_file(const std::filesystem::path& path) {
  par::silence_hdf5_error_printing();
  return {TEXSIM_HDF5_CALL(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), path.string()),
          H5Fclose};
}

} // namespace texsim::io
