#include "geom/mesh_fields.hpp"

#include <algorithm>
#include <cctype>

namespace texsim::geom {

std::vector<std::string> read_mesh_fields(const ConfigSection& section, const MeshSource& mesh) {
  const auto names = section.get<std::vector<std::string>>("mesh_fields", {});
  if (!names.empty() && mesh.file.empty())
    section.fail("mesh_fields", "no mesh fields with a generated mesh (they are point arrays of "
                                "mesh.file)");
  for (const auto& name : names) {
    const bool identifier =
        !name.empty() && !std::isdigit(static_cast<unsigned char>(name.front())) &&
        std::all_of(name.begin(), name.end(),
                    [](unsigned char c) { return std::isalnum(c) || c == '_'; });
    if (!identifier || name == "x" || name == "y" || name == "z")
      section.fail("mesh_fields", "array names usable in expressions (letters, digits, _; not "
                                  "x, y, z), got '" +
                                      name + "'");
  }
  return names;
}

} // namespace texsim::geom
