#include "io/parallel_array_declarations.hpp"

#include "io/xml_escape.hpp"

namespace texsim::io {

void write_array_declarations(std::ostream& xml, const char* tag,
                              const std::vector<DataField>& fields,
                              const std::string& texture_coordinates) {
  xml << "    <" << tag
      << (texture_coordinates.empty() ? std::string()
                                      : " TCoords=\"" + xml_escape(texture_coordinates) + "\"")
      << ">\n";
  for (const auto& field : fields)
    xml << "      <PDataArray type=\"" << field.vtk_type_name() << "\" Name=\""
        << xml_escape(field.name) << "\" NumberOfComponents=\"" << field.components << "\"/>\n";
  xml << "    </" << tag << ">\n";
}

} // namespace texsim::io
