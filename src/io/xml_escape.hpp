#pragma once
/// Escaping text for XML attribute values (file names and array names in .pvd/.pvtu headers).
#include <string>
#include <string_view>

namespace texsim::io {

/// `text` with & < > " ' replaced by their XML entities.
std::string xml_escape(std::string_view text);

} // namespace texsim::io
