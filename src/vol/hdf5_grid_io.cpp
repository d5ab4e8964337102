#include "vol/hdf5_grid_io.hpp"

#include "core/atomic_output.hpp"
#include "core/input_file.hpp"
#include "par/hdf5_call.hpp"
#include "par/hdf5_handle.hpp"
#include "vol/grid_checks.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace texsim::vol {
namespace {

void write_vector_attribute(hid_t dataset, const char* name, const std::array<double, 3>& value,
                            const std::string& context) {
  const hsize_t n = 3;
  par::Hdf5Handle space(TEXSIM_HDF5_CALL(H5Screate_simple(1, &n, nullptr), context), H5Sclose);
  par::Hdf5Handle attribute(TEXSIM_HDF5_CALL(H5Acreate2(dataset, name, H5T_IEEE_F64LE, space.get(),
                                                        H5P_DEFAULT, H5P_DEFAULT),
                                             context << " attribute " << name),
                            H5Aclose);
  TEXSIM_HDF5_CALL(H5Awrite(attribute.get(), H5T_NATIVE_DOUBLE, value.data()),
                   context << " attribute " << name);
}

/// The attribute's three values, or `fallback` if the dataset has no such attribute.
std::array<double, 3> read_vector_attribute(hid_t dataset, const char* name,
                                            const std::array<double, 3>& fallback,
                                            const std::string& context) {
  if (TEXSIM_HDF5_CALL(H5Aexists(dataset, name), context) == 0) {
    return fallback;
  }
  par::Hdf5Handle attribute(TEXSIM_HDF5_CALL(H5Aopen(dataset, name, H5P_DEFAULT), context),
                            H5Aclose);
  par::Hdf5Handle space(TEXSIM_HDF5_CALL(H5Aget_space(attribute.get()), context), H5Sclose);
  const hssize_t n = TEXSIM_HDF5_CALL(H5Sget_simple_extent_npoints(space.get()), context);
  if (n != 3) {
    TEXSIM_INPUT_ERROR(context << ": attribute '" << name << "' has " << n
                               << " values, expected 3 (x, y, z)");
  }
  std::array<double, 3> value{};
  TEXSIM_HDF5_CALL(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, value.data()),
                   context << " attribute " << name);
  return value;
}

template <class T>
void write_grid(const std::filesystem::path& path, const DenseGrid<T>& grid,
                const std::string& dataset) {
  par::silence_hdf5_error_printing();
  const std::string context = path.string() + ": dataset '" + dataset + "'";
  const Dims d = grid.dims();
  const int components = voxel_components<T>;
  const std::array<hsize_t, 4> shape{static_cast<hsize_t>(d.nz), static_cast<hsize_t>(d.ny),
                                     static_cast<hsize_t>(d.nx), 3};
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    par::Hdf5Handle file(
        TEXSIM_HDF5_CALL(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                         context),
        H5Fclose);
    par::Hdf5Handle space(
        TEXSIM_HDF5_CALL(H5Screate_simple(components == 1 ? 3 : 4, shape.data(), nullptr), context),
        H5Sclose);
    par::Hdf5Handle data(
        TEXSIM_HDF5_CALL(H5Dcreate2(file.get(), dataset.c_str(), H5T_IEEE_F32LE, space.get(),
                                    H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                         context),
        H5Dclose);
    TEXSIM_HDF5_CALL(
        H5Dwrite(data.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, grid.data().data()),
        context);
    write_vector_attribute(data.get(), "spacing", grid.spacing(), context);
    write_vector_attribute(data.get(), "origin", grid.origin(), context);
    data.reset();
    space.reset();
    TEXSIM_HDF5_CALL(file.reset(), context << ": closing");
  });
}

/// Names of the datasets directly under the root group, in name order.
std::vector<std::string> root_datasets(hid_t file, const std::string& context) {
  H5G_info_t info;
  TEXSIM_HDF5_CALL(H5Gget_info(file, &info), context);
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t length = TEXSIM_HDF5_CALL(
        H5Lget_name_by_idx(file, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT),
        context);
    std::string name(static_cast<std::size_t>(length) + 1, '\0');
    TEXSIM_HDF5_CALL(H5Lget_name_by_idx(file, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(),
                                        name.size(), H5P_DEFAULT),
                     context);
    name.resize(static_cast<std::size_t>(length));
    par::Hdf5Handle object(TEXSIM_HDF5_CALL(H5Oopen(file, name.c_str(), H5P_DEFAULT), context),
                           H5Oclose);
    if (H5Iget_type(object.get()) == H5I_DATASET) {
      names.push_back(name);
    }
  }
  return names;
}

template <class T>
AnyGrid read_values(const std::filesystem::path& path, hid_t data, const hsize_t* shape,
                    const std::string& context) {
  require_grid_fits(path, std::int64_t(std::min<hsize_t>(shape[2], INT64_MAX)),
                    std::int64_t(std::min<hsize_t>(shape[1], INT64_MAX)),
                    std::int64_t(std::min<hsize_t>(shape[0], INT64_MAX)), sizeof(T));
  DenseGrid<T> grid(
      Dims{static_cast<int>(shape[2]), static_cast<int>(shape[1]), static_cast<int>(shape[0])});
  TEXSIM_HDF5_CALL(
      H5Dread(data, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, grid.data().data()), context);
  grid.set_spacing(read_vector_attribute(data, "spacing", {1.0, 1.0, 1.0}, context));
  grid.set_origin(read_vector_attribute(data, "origin", {0.0, 0.0, 0.0}, context));
  require_finite_voxels(path, grid);
  return grid;
}

AnyGrid read_grid(const std::filesystem::path& path, const std::string& requested) {
  const std::string file_context = path.string();
  if (TEXSIM_HDF5_CALL(H5Fis_hdf5(path.c_str()), file_context) == 0) {
    TEXSIM_INPUT_ERROR(path.string() << ": not an HDF5 file");
  }
  par::Hdf5Handle file(
      TEXSIM_HDF5_CALL(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), file_context), H5Fclose);
  const std::vector<std::string> datasets = root_datasets(file.get(), file_context);
  std::string listed;
  for (const auto& name : datasets) {
    listed += (listed.empty() ? "'" : ", '") + name + "'";
  }
  const std::string name = requested.empty() && !datasets.empty() ? datasets.front() : requested;
  if (std::find(datasets.begin(), datasets.end(), name) == datasets.end()) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": no dataset" << (name.empty() ? "" : " named '" + name + "'")
                       << " in the root group, the file has "
                       << (listed.empty() ? "no datasets" : listed));
  }
  const std::string context = path.string() + ": dataset '" + name + "'";
  par::Hdf5Handle data(TEXSIM_HDF5_CALL(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), context),
                       H5Dclose);
  par::Hdf5Handle type(TEXSIM_HDF5_CALL(H5Dget_type(data.get()), context), H5Tclose);
  const H5T_class_t type_class = H5Tget_class(type.get());
  if (type_class != H5T_FLOAT && type_class != H5T_INTEGER) {
    TEXSIM_INPUT_ERROR(
        context << ": element type is not numeric, expected float or integer voxels");
  }
  par::Hdf5Handle space(TEXSIM_HDF5_CALL(H5Dget_space(data.get()), context), H5Sclose);
  const int rank = TEXSIM_HDF5_CALL(H5Sget_simple_extent_ndims(space.get()), context);
  std::array<hsize_t, 4> shape{};
  if (rank == 3 || rank == 4) {
    TEXSIM_HDF5_CALL(H5Sget_simple_extent_dims(space.get(), shape.data(), nullptr), context);
  }
  const bool empty = shape[0] == 0 || shape[1] == 0 || shape[2] == 0;
  if (rank == 3 && !empty) {
    return read_values<float>(path, data.get(), shape.data(), context);
  }
  if (rank == 4 && shape[3] == 3 && !empty) {
    return read_values<img::Rgb>(path, data.get(), shape.data(), context);
  }
  TEXSIM_INPUT_ERROR(context << ": rank " << rank << " shape [" << shape[0] << ", " << shape[1]
                             << ", " << shape[2]
                             << (rank == 4 ? ", " + std::to_string(shape[3]) : "")
                             << "], expected non-empty [nz, ny, nx] or [nz, ny, nx, 3]");
}

} // namespace

void write_hdf5_grid(const std::filesystem::path& path, const ScalarGrid& grid,
                     const std::string& dataset) {
  write_grid(path, grid, dataset);
}

void write_hdf5_grid(const std::filesystem::path& path, const RgbGrid& grid,
                     const std::string& dataset) {
  write_grid(path, grid, dataset);
}

AnyGrid read_hdf5_grid(const std::filesystem::path& path, const std::string& dataset) {
  par::silence_hdf5_error_printing();
  require_regular_file(path, "HDF5 volume (.h5, .hdf5)");
  try {
    return read_grid(path, dataset);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    // A failing HDF5 call on a file that opened as HDF5 means the file is damaged (truncated).
    throw InputError(std::string(e.what()) + " (damaged or truncated file?)");
  }
}

} // namespace texsim::vol
