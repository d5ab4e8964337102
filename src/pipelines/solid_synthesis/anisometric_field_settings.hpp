#pragma once
/// The `field:` section that picks the anisometric control of a solid synthesis run:
///   field: {type: slant, angle_degrees: 30}
///   field: {type: oval, ratio: 2}
///   field: {type: zigzag, angle_degrees: 30, bands: 4}
///   field: {type: file, file: data/fields/swirl.vti}
/// Only the keys of the chosen type are read; any other is an unknown-key error with a hint.
#include "core/config.hpp"
#include "pipelines/solid_synthesis/anisometric_field.hpp"

#include <filesystem>
#include <memory>
#include <string>

namespace texsim::pipelines::solid_synthesis {

/// The controls of Su 2008 section 5.2 plus identity (isometric) and a user vector field.
enum class FieldType { kIdentity, kCircular, kOval, kSlant, kZigzag, kSlant3d, kFile };

struct FieldSettings {
  FieldType type = FieldType::kIdentity; ///< type
  double angle_degrees = 30.0;           ///< angle_degrees (slant, zigzag, slant3d), in [-180, 180]
  double ratio = 2.0;                    ///< ratio (oval): x semi-axis over y semi-axis, > 0
  int bands = 4;                         ///< bands (zigzag): bands of each direction along y, > 0
  std::filesystem::path file; ///< file (file): .vdb (Vec3s grid), .vti or .h5/.hdf5 vectors
  std::string file_key_path;  ///< "<section>.file", for messages about the file's contents
};

/// Reads and validates the section (an absent section is the identity field). A `file` must
/// exist and have a supported extension. Throws InputError naming the key path.
FieldSettings read_field_settings(const ConfigSection& field_section);

/// Builds the field; a vector file is read here (serial, the same on every rank). Throws
/// InputError naming the key path and the file if the file cannot be read or does not hold a
/// 3-component grid.
std::unique_ptr<AxesField> make_axes_field(const FieldSettings& settings);

} // namespace texsim::pipelines::solid_synthesis
