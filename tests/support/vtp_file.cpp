#include "support/vtp_file.hpp"

#include <fstream>

namespace texsim::test {

std::filesystem::path write_vtp(const std::filesystem::path& path, const geom::TriangleMesh& mesh,
                                const std::vector<PointArray>& arrays) {
  std::ofstream out(path);
  out.precision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">\n<PolyData>\n"
      << "<Piece NumberOfPoints=\"" << mesh.positions.size() << "\" NumberOfPolys=\""
      << mesh.triangles.size() << "\">\n<PointData>\n";
  for (const auto& [name, values] : arrays) {
    out << "<DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
    for (const double v : values)
      out << v << "\n";
    out << "</DataArray>\n";
  }
  out << "</PointData>\n<Points>\n"
      << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : mesh.positions)
    out << p.x() << " " << p.y() << " " << p.z() << "\n";
  out << "</DataArray>\n</Points>\n<Polys>\n"
      << "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : mesh.triangles)
    out << t[0] << " " << t[1] << " " << t[2] << "\n";
  out << "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t k = 1; k <= mesh.triangles.size(); ++k)
    out << 3 * k << "\n";
  out << "</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
  return path;
}

} // namespace texsim::test
