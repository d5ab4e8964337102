#pragma once
/// Scalar attributes (int64, uint64, double, string) on an HDF5 object. Writing an attribute of a
/// file opened with MPI-IO is collective: every rank passes the same value.
#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>

namespace texsim::io {

using AttributeValue = std::variant<std::int64_t, std::uint64_t, double, std::string>;

/// Creates attribute `name` on `object` holding `value`; `file` names the file in errors.
void write_attribute(hid_t object, const std::string& name, const AttributeValue& value,
                     const std::filesystem::path& file);

/// Whether `object` has an attribute `name`.
bool has_attribute(hid_t object, const std::string& name, const std::filesystem::path& file);

/// The value of attribute `name` of `object`, in the alternative matching its stored type.
/// Throws texsim::Error if it is missing or of another kind.
AttributeValue read_attribute(hid_t object, const std::string& name,
                              const std::filesystem::path& file);

} // namespace texsim::io
