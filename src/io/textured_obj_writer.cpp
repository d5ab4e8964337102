#include "io/textured_obj_writer.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string_view>
#include <vector>

namespace texsim::io {
namespace {

/// Appends `value` in the shortest decimal form that reads back to the same double.
void append_number(std::string& out, double value) {
  std::array<char, 32> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  TEXSIM_VERIFY(error == std::errc(), "cannot format " << value);
  out.append(buffer.data(), end);
}

void append_numbers(std::string& out, std::string_view keyword, std::span<const double> values) {
  out += keyword;
  for (const double value : values) {
    out += ' ';
    append_number(out, value);
  }
  out += '\n';
}

/// A name OBJ and MTL lines can hold: not empty, no whitespace or line breaks.
bool plain_name(const std::string& name) {
  return !name.empty() && std::none_of(name.begin(), name.end(), [](char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
  });
}

void check_surface(const std::filesystem::path& path, const TexturedSurface& surface,
                   const ObjMaterial& material, const std::string& mtl_name) {
  TEXSIM_VERIFY(surface.xyz.size() % 3 == 0 && surface.triangles.size() % 3 == 0,
                path.string() << ": " << surface.xyz.size() << " coordinates and "
                              << surface.triangles.size()
                              << " triangle indices are not multiples of 3");
  const std::size_t vertices = surface.xyz.size() / 3;
  const std::size_t triangles = surface.triangles.size() / 3;
  TEXSIM_VERIFY(surface.corner_uv.size() == 6 * triangles,
                path.string() << ": " << surface.corner_uv.size() << " corner uv values for "
                              << triangles << " triangles, expected " << 6 * triangles);
  TEXSIM_VERIFY(surface.normals.empty() || surface.normals.size() == surface.xyz.size(),
                path.string() << ": " << surface.normals.size() << " normal components for "
                              << vertices << " vertices, expected " << surface.xyz.size()
                              << " or none");
  for (const auto values : {surface.xyz, surface.corner_uv, surface.normals}) {
    TEXSIM_VERIFY(
        std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); }),
        path.string() << ": a coordinate, uv or normal is not finite");
  }
  for (std::size_t i = 0; i < surface.triangles.size(); ++i) {
    const std::int32_t v = surface.triangles[i];
    TEXSIM_VERIFY(v >= 0 && static_cast<std::size_t>(v) < vertices,
                  path.string() << ": triangle " << i / 3 << " has vertex " << v << ", outside [0, "
                                << vertices << ")");
  }
  TEXSIM_VERIFY(plain_name(material.name) && plain_name(material.texture_file) &&
                    plain_name(mtl_name),
                path.string() << ": the material name '" << material.name << "', texture file '"
                              << material.texture_file << "' and material library '" << mtl_name
                              << "' must be non-empty and free of spaces and line breaks");
}

std::string mtl_text(const ObjMaterial& material) {
  return "# texsim texture atlas material\nnewmtl " + material.name +
         "\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\nmap_Kd " + material.texture_file + "\n";
}

/// vt index (from 0) of each triangle corner: one per distinct (vertex, uv) pair, numbered in
/// order of first use; `uv_of_vt` receives their values.
std::vector<std::int64_t> texture_vertices(const TexturedSurface& surface,
                                           std::vector<std::array<double, 2>>& uv_of_vt) {
  const std::size_t vertices = surface.xyz.size() / 3;
  // Distinct uv pairs seen at each vertex, as vt indices; a vertex has one per chart it is in.
  std::vector<std::vector<std::int64_t>> seen(vertices);
  std::vector<std::int64_t> corner_vt(surface.triangles.size());
  for (std::size_t corner = 0; corner < surface.triangles.size(); ++corner) {
    const std::array<double, 2> uv{surface.corner_uv[2 * corner],
                                   surface.corner_uv[2 * corner + 1]};
    auto& at_vertex = seen[surface.triangles[corner]];
    const auto same = std::find_if(at_vertex.begin(), at_vertex.end(),
                                   [&](std::int64_t vt) { return uv_of_vt[vt] == uv; });
    if (same != at_vertex.end()) {
      corner_vt[corner] = *same;
    } else {
      corner_vt[corner] = static_cast<std::int64_t>(uv_of_vt.size());
      at_vertex.push_back(corner_vt[corner]);
      uv_of_vt.push_back(uv);
    }
  }
  return corner_vt;
}

/// Bytes of OBJ text gathered before they are handed on: the text of a large surface is never
/// held whole.
constexpr std::size_t kObjPartBytes = std::size_t{1} << 20;

void emit_obj_text(const TexturedSurface& surface, const ObjMaterial& material,
                   const std::string& mtl_name, const TextSink& emit) {
  std::string out = "# texsim textured surface\nmtllib " + mtl_name + "\n";
  const auto pass_on_full = [&] {
    if (out.size() >= kObjPartBytes) {
      emit(out);
      out.clear();
    }
  };
  for (std::size_t v = 0; v < surface.xyz.size(); v += 3) {
    append_numbers(out, "v", surface.xyz.subspan(v, 3));
    pass_on_full();
  }
  std::vector<std::array<double, 2>> uv_of_vt;
  const std::vector<std::int64_t> corner_vt = texture_vertices(surface, uv_of_vt);
  for (const auto& uv : uv_of_vt) {
    append_numbers(out, "vt", uv);
    pass_on_full();
  }
  for (std::size_t v = 0; v < surface.normals.size(); v += 3) {
    append_numbers(out, "vn", surface.normals.subspan(v, 3));
    pass_on_full();
  }
  out += "usemtl " + material.name + "\n";
  const bool with_normals = !surface.normals.empty();
  for (std::size_t corner = 0; corner < surface.triangles.size(); ++corner) {
    const std::string vertex = std::to_string(surface.triangles[corner] + 1);
    out += corner % 3 == 0 ? "f " : " ";
    out += vertex + '/' + std::to_string(corner_vt[corner] + 1);
    if (with_normals) {
      out += '/' + vertex;
    }
    if (corner % 3 == 2) {
      out += '\n';
      pass_on_full();
    }
  }
  emit(out);
}

} // namespace

void write_textured_obj(const std::filesystem::path& obj_path, const TexturedSurface& surface,
                        const ObjMaterial& material) {
  const std::filesystem::path mtl_path = std::filesystem::path(obj_path).replace_extension(".mtl");
  const std::string mtl_name = mtl_path.filename().string();
  check_surface(obj_path, surface, material, mtl_name);
  write_atomically(mtl_path, mtl_text(material));
  write_atomically_in_parts(
      obj_path, [&](const TextSink& emit) { emit_obj_text(surface, material, mtl_name, emit); });
}

} // namespace texsim::io
