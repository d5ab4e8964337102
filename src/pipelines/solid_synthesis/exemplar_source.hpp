#pragma once
/// Where the solid synthesis' exemplar comes from, as the `exemplar:` config section: a volume
/// file or a procedural generator, and how its faces are treated:
///   exemplar: {file: data/volumes/granite.vti, border: discard}
///   exemplar: {procedural: lattice, size: 32, period: 8, seed: 3}
#include "core/config.hpp"
#include "par/comm.hpp"
#include "pipelines/solid_synthesis/appearance_space.hpp"
#include "vol/channel_grid.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace texsim::pipelines::solid_synthesis {

/// The procedural generators of vol/procedural_exemplars.hpp.
enum class ProceduralExemplar { marble, particles, wood, bricks, noise, strokes, stripes, lattice };

struct ExemplarSettings {
  /// file: a .vdb, .vti, .h5/.hdf5 or .inr volume (then none of the procedural keys apply).
  std::optional<std::filesystem::path> file;
  ProceduralExemplar procedural = ProceduralExemplar::marble; ///< procedural: generator name
  int size = 64;          ///< size: edge of the procedural size^3 exemplar, voxels (>= 8)
  int period = 8;         ///< period: lattice cell edge, voxels (size a multiple of it)
  std::uint64_t seed = 1; ///< seed: of the procedural generator
  ExemplarBorder border = ExemplarBorder::toroidal; ///< border: toroidal or discard
  std::string key_path; ///< the section's key path ("solid_synthesis.exemplar"), for messages
};

/// Reads the section: `file` or `procedural` (marble, particles, wood, bricks, noise, strokes,
/// stripes, lattice; default marble) with `size`, `seed` and, for lattice only, `period`; and
/// `border`. A file must exist and have a supported extension. Throws InputError naming the key
/// path.
ExemplarSettings read_exemplar_settings(const ConfigSection& exemplar_section);

/// An exemplar ready for build_appearance_space.
struct Exemplar {
  vol::ChannelGrid colours; ///< 3 channels, or 1 for a scalar file rescaled to [0, 1]
  bool scalar = false;      ///< the file held a scalar grid
  std::string description;  ///< "file data/x.vti" or "procedural marble 64^3, seed 1"
  std::string content_hash; ///< 16 hex digits over the dims, channel count and values
};

/// Reads the file (scalar grids rescaled linearly from [min, max] to [0, 1], a constant grid
/// becoming 0; colour grids as stored) or runs the generator. Serial; the same on every rank.
/// Throws InputError naming the key path and the file if the file cannot be read.
Exemplar load_exemplar(const ExemplarSettings& settings);

/// load_exemplar on `comm`'s rank 0 only: the colours are then held once per node (a read-only
/// node-shared grid; no other rank ever holds a copy, and rank 0's own is freed on return), the
/// description, hash and kind broadcast. A failure on rank 0 (InputError naming the file) is
/// thrown on every rank. Collective.
Exemplar load_exemplar_once_per_node(const par::Comm& comm, const ExemplarSettings& settings);

/// Throws InputError naming the settings' key path when the exemplar is smaller than 2 * window
/// voxels along an axis: too few distinct neighbourhoods to learn from and to synthesize with.
void require_exemplar_fits_window(const Exemplar& exemplar, const ExemplarSettings& settings,
                                  int window);

} // namespace texsim::pipelines::solid_synthesis
