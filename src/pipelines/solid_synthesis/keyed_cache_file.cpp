#include "pipelines/solid_synthesis/keyed_cache_file.hpp"

#include "core/atomic_output.hpp"
#include "io/hdf5_attribute.hpp"
#include "io/hdf5_file.hpp"
#include "par/hdf5_call.hpp"

#include <system_error>
#include <variant>

namespace texsim::pipelines::solid_synthesis {

std::optional<par::Hdf5Handle> open_cache_file(const std::filesystem::path& file,
                                               const std::string& key,
                                               std::int64_t format_version) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error))
    return std::nullopt;
  par::silence_hdf5_error_printing();
  if (H5Fis_hdf5(file.c_str()) <= 0)
    return std::nullopt;
  par::Hdf5Handle h5 = io::open_serial_file(file);
  if (std::get<std::int64_t>(io::read_attribute(h5.get(), "format_version", file)) !=
          format_version ||
      std::get<std::string>(io::read_attribute(h5.get(), "key", file)) != key)
    return std::nullopt;
  return h5;
}

void write_cache_file(const std::filesystem::path& file, const std::string& key,
                      std::int64_t format_version,
                      const std::function<void(hid_t, const std::filesystem::path&)>& fill) {
  if (file.has_parent_path())
    std::filesystem::create_directories(file.parent_path());
  write_atomically(file, [&](const std::filesystem::path& temporary) {
    par::silence_hdf5_error_printing();
    par::Hdf5Handle h5(
        TEXSIM_HDF5_CALL(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                         file.string()),
        H5Fclose);
    fill(h5.get(), file);
    io::write_attribute(h5.get(), "format_version", format_version, file);
    io::write_attribute(h5.get(), "key", key, file);
    TEXSIM_HDF5_CALL(h5.reset(), file.string() << ": closing");
  });
}

} // namespace texsim::pipelines::solid_synthesis
