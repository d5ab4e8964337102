#include "pipelines/solid_synthesis/anisometric_field_settings.hpp"

#include "vol/hdf5_grid_io.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <algorithm>
#include <cctype>
#include <variant>

namespace texsim::pipelines::solid_synthesis {
namespace {

std::string lower_case_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool is_vector_file_extension(const std::string& ext) {
  return ext == ".vdb" || ext == ".vti" || ext == ".h5" || ext == ".hdf5";
}

/// The grid of a vector file, read by extension (checked in read_field_settings).
vol::AnyGrid read_vector_file(const std::filesystem::path& path) {
  const std::string ext = lower_case_extension(path);
  if (ext == ".vdb") {
    return vol::read_vdb(path);
  }
  if (ext == ".vti") {
    return vol::read_vti(path);
  }
  return vol::read_hdf5_grid(path);
}

} // namespace

FieldSettings read_field_settings(const ConfigSection& field_section) {
  FieldSettings settings;
  settings.type = field_section.choice<FieldType>("type", FieldType::kIdentity,
                                                  {{"identity", FieldType::kIdentity},
                                                   {"circular", FieldType::kCircular},
                                                   {"oval", FieldType::kOval},
                                                   {"slant", FieldType::kSlant},
                                                   {"zigzag", FieldType::kZigzag},
                                                   {"slant3d", FieldType::kSlant3d},
                                                   {"file", FieldType::kFile}});
  const FieldType type = settings.type;
  if (type == FieldType::kSlant || type == FieldType::kZigzag || type == FieldType::kSlant3d) {
    settings.angle_degrees =
        field_section.get<double>("angle_degrees", settings.angle_degrees, in_range(-180, 180));
  }
  if (type == FieldType::kOval) {
    settings.ratio = field_section.get<double>("ratio", settings.ratio, positive());
  }
  if (type == FieldType::kZigzag) {
    settings.bands = field_section.get<int>("bands", settings.bands, positive_int());
  }
  if (type == FieldType::kFile) {
    settings.file = field_section.require<std::string>("file");
    settings.file_key_path = field_section.key_path("file");
    if (!is_vector_file_extension(lower_case_extension(settings.file))) {
      field_section.fail("file", "a vector field file (.vdb, .vti, .h5 or .hdf5)");
    }
    if (!std::filesystem::is_regular_file(settings.file)) {
      field_section.fail("file", "an existing vector field file (.vdb, .vti, .h5 or .hdf5)");
    }
  }
  return settings;
}

std::unique_ptr<AxesField> make_axes_field(const FieldSettings& settings) {
  switch (settings.type) {
  case FieldType::kIdentity:
    return identity_field();
  case FieldType::kCircular:
    return ellipse_field(1.0);
  case FieldType::kOval:
    return ellipse_field(settings.ratio);
  case FieldType::kSlant:
    return rotation_field(Eigen::Vector3d::UnitZ(), settings.angle_degrees);
  case FieldType::kZigzag:
    return zigzag_field(settings.angle_degrees, settings.bands);
  case FieldType::kSlant3d:
    return rotation_field(Eigen::Vector3d::Ones(), settings.angle_degrees);
  case FieldType::kFile:
    break;
  }
  vol::AnyGrid grid;
  try {
    grid = read_vector_file(settings.file);
  } catch (const InputError& e) {
    TEXSIM_INPUT_ERROR(settings.file_key_path << ": " << e.what());
  }
  auto* vectors = std::get_if<vol::RgbGrid>(&grid);
  if (vectors == nullptr) {
    TEXSIM_INPUT_ERROR(settings.file_key_path
                       << ": " << settings.file.string()
                       << " holds a scalar grid, expected 3 components (a vector) per voxel");
  }
  return vector_grid_field(std::move(*vectors));
}

} // namespace texsim::pipelines::solid_synthesis
