#include "io/textured_obj_writer.hpp"

#include "core/error.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/texture_atlas.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace texsim::io {
namespace {

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The OBJ's lines by keyword, numbers parsed back with strtod.
struct ParsedObj {
  std::vector<std::array<double, 3>> v, vn;
  std::vector<std::array<double, 2>> vt;
  std::vector<std::array<std::array<int, 3>, 3>> f; ///< per corner: v, vt, vn (0 when absent)
  std::string mtllib, usemtl;
};

ParsedObj parse_obj(const std::filesystem::path& path) {
  ParsedObj obj;
  std::istringstream lines(read_text(path));
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    const auto numbers = [&](auto& out) {
      std::string word;
      for (auto& value : out.emplace_back()) {
        words >> word;
        value = std::strtod(word.c_str(), nullptr);
      }
    };
    if (keyword == "v") {
      numbers(obj.v);
    } else if (keyword == "vt") {
      numbers(obj.vt);
    } else if (keyword == "vn") {
      numbers(obj.vn);
    } else if (keyword == "mtllib") {
      words >> obj.mtllib;
    } else if (keyword == "usemtl") {
      words >> obj.usemtl;
    } else if (keyword == "f") {
      auto& face = obj.f.emplace_back();
      for (auto& corner : face) {
        std::string word;
        words >> word;
        corner = {0, 0, 0};
        std::istringstream parts(word);
        std::string part;
        for (int i = 0; i < 3 && std::getline(parts, part, '/'); ++i) {
          corner[i] = part.empty() ? 0 : std::stoi(part);
        }
      }
    }
  }
  return obj;
}

/// Two triangles sharing the edge 1-2, cut apart in uv (vertex 1 and 2 have two uvs each).
struct Seam {
  std::vector<double> xyz{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.1};
  std::vector<std::int32_t> triangles{0, 1, 2, 2, 1, 3};
  std::vector<double> corner_uv{0.1, 0.1, 0.4, 0.1, 0.1, 0.4,  // first chart
                                0.6, 0.9, 0.6, 0.6, 0.9, 0.9}; // second chart
  std::vector<double> normals{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};

  TexturedSurface surface(bool with_normals) const {
    return {xyz, triangles, corner_uv,
            with_normals ? std::span<const double>(normals) : std::span<const double>()};
  }
};

TEST(TexturedObjWriter, WritesVerticesSharedUvsAndFacesThatParseBackExactly) {
  const auto dir = test::scratch_dir("textured_obj_seam");
  const Seam seam;
  write_textured_obj(dir / "textured.obj", seam.surface(false));
  const ParsedObj obj = parse_obj(dir / "textured.obj");
  EXPECT_EQ(obj.mtllib, "textured.mtl");
  EXPECT_EQ(obj.usemtl, "atlas");
  ASSERT_EQ(obj.v.size(), 4u);
  for (std::size_t i = 0; i < seam.xyz.size(); ++i) {
    EXPECT_EQ(obj.v[i / 3][i % 3], seam.xyz[i]);
  }
  EXPECT_EQ(obj.vt.size(), 6u); // vertices 1 and 2 have a uv in each chart
  EXPECT_TRUE(obj.vn.empty());
  ASSERT_EQ(obj.f.size(), 2u);
  for (std::size_t corner = 0; corner < 6; ++corner) {
    const auto& [v, vt, vn] = obj.f[corner / 3][corner % 3];
    EXPECT_EQ(v, seam.triangles[corner] + 1);
    EXPECT_EQ(obj.vt.at(vt - 1)[0], seam.corner_uv[2 * corner]);
    EXPECT_EQ(obj.vt.at(vt - 1)[1], seam.corner_uv[2 * corner + 1]);
    EXPECT_EQ(vn, 0);
  }
  const std::string mtl = read_text(dir / "textured.mtl");
  EXPECT_NE(mtl.find("newmtl atlas\n"), std::string::npos);
  EXPECT_NE(mtl.find("map_Kd atlas.png\n"), std::string::npos);
  EXPECT_TRUE(test::temporary_files_under(dir).empty());
}

TEST(TexturedObjWriter, WritesNormalsAndTheMaterialGiven) {
  const auto dir = test::scratch_dir("textured_obj_normals");
  const Seam seam;
  write_textured_obj(dir / "surface.obj", seam.surface(true), {"pebbles", "maps/pebbles.png"});
  const ParsedObj obj = parse_obj(dir / "surface.obj");
  EXPECT_EQ(obj.mtllib, "surface.mtl");
  EXPECT_EQ(obj.usemtl, "pebbles");
  ASSERT_EQ(obj.vn.size(), 4u);
  for (const auto& face : obj.f) {
    for (const auto& corner : face) {
      EXPECT_EQ(corner[2], corner[0]);
    }
  }
  EXPECT_NE(read_text(dir / "surface.mtl").find("map_Kd maps/pebbles.png\n"), std::string::npos);
}

TEST(TexturedObjWriter, RefusesInconsistentArraysAndLeavesEarlierFiles) {
  const auto dir = test::scratch_dir("textured_obj_refusals");
  const Seam seam;
  write_textured_obj(dir / "textured.obj", seam.surface(false));
  const std::string before = read_text(dir / "textured.obj");

  Seam bad = seam;
  bad.triangles[4] = 4; // vertex out of range
  EXPECT_THROW(write_textured_obj(dir / "textured.obj", bad.surface(false)), Error);
  bad = seam;
  bad.corner_uv.pop_back();
  EXPECT_THROW(write_textured_obj(dir / "textured.obj", bad.surface(false)), Error);
  bad = seam;
  bad.xyz[2] = std::nan("");
  EXPECT_THROW(write_textured_obj(dir / "textured.obj", bad.surface(false)), Error);
  bad = seam;
  bad.normals.pop_back();
  EXPECT_THROW(write_textured_obj(dir / "textured.obj", bad.surface(true)), Error);
  EXPECT_THROW(write_textured_obj(dir / "textured.obj", seam.surface(false), {"my atlas", "a.png"}),
               Error);
  EXPECT_THROW(write_textured_obj(dir / "textured.obj", seam.surface(false), {"atlas", ""}), Error);

  EXPECT_EQ(read_text(dir / "textured.obj"), before);
  EXPECT_TRUE(test::temporary_files_under(dir).empty());
}

/// The atlas of `mesh` written as OBJ reads back through geom::read_mesh (VTK's OBJ reader, then
/// coincident vertices merged) with the same triangles, and VTK sees each corner's uv.
void expect_round_trip(const geom::TriangleMesh& mesh, const std::string& name) {
  const geom::TextureAtlas atlas = geom::build_texture_atlas(mesh, {256, 1, 5000, 60.0});
  std::vector<double> xyz, corner_uv;
  std::vector<std::int32_t> triangles;
  for (const auto& p : mesh.positions) {
    xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  }
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    triangles.insert(triangles.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
    for (const auto& uv : atlas.corner_uv[t]) {
      corner_uv.insert(corner_uv.end(), {uv.x(), uv.y()});
    }
  }
  const auto path = test::scratch_dir("textured_obj_" + name) / "textured.obj";
  write_textured_obj(path, {xyz, triangles, corner_uv, {}});

  // Triangles as vertex-position triples, starting at the smallest position (orientation kept).
  using Corner = std::array<float, 3>;
  const auto triangle_set = [](const geom::TriangleMesh& m) {
    std::vector<std::array<Corner, 3>> out;
    for (const auto& tri : m.triangles) {
      std::array<Corner, 3> corners;
      for (int i = 0; i < 3; ++i) {
        const auto& p = m.positions[tri[i]];
        corners[i] = {float(p.x()), float(p.y()), float(p.z())};
      }
      std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
      out.push_back(corners);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  const geom::TriangleMesh back = geom::read_mesh(path);
  EXPECT_EQ(back.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(triangle_set(back), triangle_set(mesh));

  // VTK's reader gives every corner its own point when uvs differ; each face's points carry the
  // written uv (as VTK's float).
  vtkNew<vtkOBJReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* data = reader->GetOutput();
  vtkDataArray* tcoords = data->GetPointData()->GetTCoords();
  ASSERT_NE(tcoords, nullptr);
  ASSERT_EQ(data->GetNumberOfCells(), mesh.num_triangles());
  for (vtkIdType t = 0; t < data->GetNumberOfCells(); ++t) {
    vtkIdType count = 0;
    const vtkIdType* points = nullptr;
    data->GetCellPoints(t, count, points);
    ASSERT_EQ(count, 3);
    for (int i = 0; i < 3; ++i) {
      EXPECT_FLOAT_EQ(float(tcoords->GetComponent(points[i], 0)), float(atlas.corner_uv[t][i].x()));
      EXPECT_FLOAT_EQ(float(tcoords->GetComponent(points[i], 1)), float(atlas.corner_uv[t][i].y()));
    }
  }
}

TEST(TexturedObjWriter, AtlasOfASphereAndATorusRoundTripsThroughTheMeshReader) {
  expect_round_trip(geom::icosphere(2), "sphere");
  expect_round_trip(geom::torus(1.0, 0.4, 16, 8), "torus");
}

TEST(TexturedObjWriterOnRealData, FandiskAtlasRoundTripsThroughTheMeshReader) {
  const auto path = test::real_data("meshes/fandisk.off");
  if (path.empty()) {
    GTEST_SKIP() << test::missing_data_message("meshes/fandisk.off");
  }
  expect_round_trip(geom::read_mesh(path), "fandisk");
}

} // namespace
} // namespace texsim::io
