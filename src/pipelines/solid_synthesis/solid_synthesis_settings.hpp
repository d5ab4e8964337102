#pragma once
/// The `solid_synthesis:` config section, read into typed settings (see
/// config/solid_synthesis/*.yaml and docs/solid_synthesis.md for every key).
#include "core/config.hpp"
#include "pipelines/solid_synthesis/anisometric_field_settings.hpp"
#include "pipelines/solid_synthesis/appearance_space.hpp"
#include "pipelines/solid_synthesis/exemplar_source.hpp"
#include "pipelines/solid_synthesis/pyramid_synthesizer.hpp"
#include "pipelines/solid_synthesis/similarity_sets.hpp"
#include "vol/vdb_dense_layout.hpp"

#include <array>
#include <filesystem>
#include <optional>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// How far a run goes: the whole synthesis, or only the precomputation (features and similarity
/// sets, stored in the cache for later syntheses).
enum class RunMode { synthesis, similarity_sets };

struct SolidSynthesisSettings {
  RunMode mode = RunMode::synthesis;
  ExemplarSettings exemplar;
  AppearanceOptions appearance;
  SimilarityOptions similarity;
  /// Where similarity sets are kept between runs (keyed by features and options); empty: no cache.
  std::filesystem::path cache_dir = "cache/solid_synthesis";
  /// Result size in voxels; the pyramid is the next power of two, cropped at the end.
  std::array<int, 3> dims{128, 128, 128};
  SynthesisOptions synthesis;         ///< `levels` follows from dims
  std::optional<FieldSettings> field; ///< absent: isometric synthesis
  /// X = Y = Z positions of the PNG cross-sections (the thesis' figures use 126, 80 and 64).
  std::vector<int> cross_sections;
  /// How solid_synthesis.vdb stores its leaves (vdb_compression: blosc, OpenVDB's default; zip;
  /// none).
  vol::VdbCompression vdb_compression = vol::VdbCompression::blosc;
  /// Every stride-th voxel along each axis enters the neighbourhood-error metric (0: automatic,
  /// about 32^3 samples).
  int metric_stride = 0;
};

SolidSynthesisSettings read_solid_synthesis_settings(const ConfigSection& section);

} // namespace texsim::pipelines::solid_synthesis
