#pragma once
/// The array declarations of VTK's parallel XML headers (.pvtp, .pvtu, .pvti): one PDataArray
/// per field, with its type, name and components, inside <PPointData> or <PCellData>.
#include "io/surface_piece.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace texsim::io {

/// Writes <tag> (with TCoords naming `texture_coordinates` when not empty), the fields'
/// PDataArray elements and </tag>, indented as a child of the dataset element.
void write_array_declarations(std::ostream& xml, const char* tag,
                              const std::vector<DataField>& fields,
                              const std::string& texture_coordinates = "");

} // namespace texsim::io
