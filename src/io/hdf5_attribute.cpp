#include "io/hdf5_attribute.hpp"

#include "par/hdf5_call.hpp"
#include "par/hdf5_handle.hpp"

#include <algorithm>
#include <vector>

namespace texsim::io {
namespace {

par::Hdf5Handle string_type(std::size_t length, const std::filesystem::path& file) {
  par::Hdf5Handle type(TEXSIM_HDF5_CALL(H5Tcopy(H5T_C_S1), file.string()), H5Tclose);
  TEXSIM_HDF5_CALL(H5Tset_size(type.get(), std::max<std::size_t>(length, 1)), file.string());
  TEXSIM_HDF5_CALL(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), file.string());
  return type;
}

} // namespace

void write_attribute(hid_t object, const std::string& name, const AttributeValue& value,
                     const std::filesystem::path& file) {
  const par::Hdf5Handle space(TEXSIM_HDF5_CALL(H5Screate(H5S_SCALAR), file.string()), H5Sclose);
  par::Hdf5Handle string_holder;
  hid_t type = H5I_INVALID_HID;
  const void* data = nullptr;
  if (const auto* v = std::get_if<std::int64_t>(&value)) {
    type = H5T_NATIVE_INT64;
    data = v;
  } else if (const auto* u = std::get_if<std::uint64_t>(&value)) {
    type = H5T_NATIVE_UINT64;
    data = u;
  } else if (const auto* d = std::get_if<double>(&value)) {
    type = H5T_NATIVE_DOUBLE;
    data = d;
  } else {
    const auto& text = std::get<std::string>(value);
    string_holder = string_type(text.size(), file);
    type = string_holder.get();
    data = text.empty() ? "" : text.data();
  }
  const par::Hdf5Handle attribute(
      TEXSIM_HDF5_CALL(
          H5Acreate2(object, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
          file.string()),
      H5Aclose);
  TEXSIM_HDF5_CALL(H5Awrite(attribute.get(), type, data), file.string());
}

bool has_attribute(hid_t object, const std::string& name, const std::filesystem::path& file) {
  return TEXSIM_HDF5_CALL(H5Aexists(object, name.c_str()), file.string()) > 0;
}

AttributeValue read_attribute(hid_t object, const std::string& name,
                              const std::filesystem::path& file) {
  TEXSIM_VERIFY(has_attribute(object, name, file),
                file.string() << ": attribute '" << name << "' is missing");
  const par::Hdf5Handle attribute(
      TEXSIM_HDF5_CALL(H5Aopen(object, name.c_str(), H5P_DEFAULT), file.string()), H5Aclose);
  const par::Hdf5Handle type(TEXSIM_HDF5_CALL(H5Aget_type(attribute.get()), file.string()),
                             H5Tclose);
  const H5T_class_t type_class = H5Tget_class(type.get());
  if (type_class == H5T_STRING) {
    TEXSIM_VERIFY(H5Tis_variable_str(type.get()) == 0,
                  file.string() << ": attribute '" << name << "' is a variable-length string");
    const std::size_t size = H5Tget_size(type.get());
    std::vector<char> buffer(size);
    TEXSIM_HDF5_CALL(H5Aread(attribute.get(), type.get(), buffer.data()), file.string());
    std::string text(buffer.begin(), buffer.end());
    text.erase(std::find(text.begin(), text.end(), '\0'), text.end());
    return text;
  }
  if (type_class == H5T_FLOAT) {
    double value = 0;
    TEXSIM_HDF5_CALL(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value), file.string());
    return value;
  }
  TEXSIM_VERIFY(type_class == H5T_INTEGER,
                file.string() << ": attribute '" << name << "' is neither a number nor a string");
  if (H5Tget_sign(type.get()) == H5T_SGN_NONE) {
    std::uint64_t value = 0;
    TEXSIM_HDF5_CALL(H5Aread(attribute.get(), H5T_NATIVE_UINT64, &value), file.string());
    return value;
  }
  std::int64_t value = 0;
  TEXSIM_HDF5_CALL(H5Aread(attribute.get(), H5T_NATIVE_INT64, &value), file.string());
  return value;
}

} // namespace texsim::io
