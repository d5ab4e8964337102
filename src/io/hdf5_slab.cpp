#include "io/hdf5_slab.hpp"

#include "core/error.hpp"
#include "par/hdf5_call.hpp"
#include "par/hdf5_handle.hpp"

namespace texsim::io {

std::vector<hsize_t> dataset_shape(hid_t dataset, const std::string& where) {
  const par::Hdf5Handle space(TEXSIM_HDF5_CALL(H5Dget_space(dataset), where), H5Sclose);
  std::vector<hsize_t> shape(
      static_cast<std::size_t>(TEXSIM_HDF5_CALL(H5Sget_simple_extent_ndims(space.get()), where)));
  TEXSIM_HDF5_CALL(H5Sget_simple_extent_dims(space.get(), shape.data(), nullptr), where);
  return shape;
}

void read_leading_slab(hid_t dataset, std::uint64_t begin, std::uint64_t end, ScalarType type,
                       void* out, std::size_t out_count, const std::string& where) {
  const par::Hdf5Handle file_space(TEXSIM_HDF5_CALL(H5Dget_space(dataset), where), H5Sclose);
  std::vector<hsize_t> count = dataset_shape(dataset, where);
  TEXSIM_VERIFY(!count.empty() && begin <= end && end <= count.front(),
                where << ": indices [" << begin << ", " << end << ") of a dataset of "
                      << (count.empty() ? 0 : count.front()) << " along its first axis");
  count.front() = end - begin;
  std::uint64_t elements = 1;
  for (const hsize_t extent : count)
    elements *= extent;
  TEXSIM_VERIFY(elements == out_count,
                where << ": the slab holds " << elements << " values, not " << out_count);
  if (elements == 0)
    return;
  std::vector<hsize_t> start(count.size(), 0);
  start.front() = begin;
  TEXSIM_HDF5_CALL(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr,
                                       count.data(), nullptr),
                   where);
  const par::Hdf5Handle memory_space(
      TEXSIM_HDF5_CALL(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr),
                       where),
      H5Sclose);
  TEXSIM_HDF5_CALL(H5Dread(dataset, native_hdf5_type(type), memory_space.get(), file_space.get(),
                           H5P_DEFAULT, out),
                   where);
}

} // namespace texsim::io
