#include "pipelines/solid_synthesis/exemplar_source.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "par/collective.hpp"
#include "par/node_shared_array.hpp"
#include "par/record_exchange.hpp"
#include "vol/hdf5_grid_io.hpp"
#include "vol/inr_reader.hpp"
#include "vol/procedural_exemplars.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

constexpr int kMinSize = 8;
constexpr int kMaxSize = 512;

const std::array<std::pair<const char*, ProceduralExemplar>, 8> kGenerators{{
    {"marble", ProceduralExemplar::marble},
    {"particles", ProceduralExemplar::particles},
    {"wood", ProceduralExemplar::wood},
    {"bricks", ProceduralExemplar::bricks},
    {"noise", ProceduralExemplar::noise},
    {"strokes", ProceduralExemplar::strokes},
    {"stripes", ProceduralExemplar::stripes},
    {"lattice", ProceduralExemplar::lattice},
}};

std::string generator_name(ProceduralExemplar generator) {
  for (const auto& [name, value] : kGenerators) {
    if (value == generator) {
      return name;
    }
  }
  return "unknown";
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// The grid of a volume file as stored, by extension.
vol::AnyGrid read_grid(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".vdb") {
    return vol::read_vdb(path);
  }
  if (ext == ".vti") {
    return vol::read_vti(path);
  }
  if (ext == ".h5" || ext == ".hdf5") {
    return vol::read_hdf5_grid(path);
  }
  return vol::read_inr(path);
}

bool supported_extension(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".vdb" || ext == ".vti" || ext == ".h5" || ext == ".hdf5" || ext == ".inr";
}

/// One channel, rescaled linearly from [min, max] to [0, 1] (a constant grid becomes 0).
vol::ChannelGrid unit_range_channel(const vol::ScalarGrid& grid) {
  vol::ChannelGrid out = vol::to_channels(grid);
  const auto [lo, hi] = std::minmax_element(out.data().begin(), out.data().end());
  const float low = *lo, range = *hi - *lo;
  for (float& v : out.data()) {
    v = range > 0.0f ? (v - low) / range : 0.0f;
  }
  return out;
}

vol::RgbGrid generate(const ExemplarSettings& s) {
  switch (s.procedural) {
  case ProceduralExemplar::marble:
    return vol::marble_exemplar(s.size, s.seed);
  case ProceduralExemplar::particles:
    return vol::particle_exemplar(s.size, s.seed);
  case ProceduralExemplar::wood:
    return vol::wood_exemplar(s.size, s.seed);
  case ProceduralExemplar::bricks:
    return vol::brick_exemplar(s.size, s.seed);
  case ProceduralExemplar::noise:
    return vol::noise_exemplar(s.size, s.seed);
  case ProceduralExemplar::strokes:
    return vol::stroke_exemplar(s.size, s.seed);
  case ProceduralExemplar::stripes:
    return vol::stripe_exemplar(s.size);
  case ProceduralExemplar::lattice:
    return vol::lattice_exemplar(s.size, s.period, s.seed);
  }
  TEXSIM_VERIFY(false, "unhandled procedural exemplar " << static_cast<int>(s.procedural));
}

std::string content_hash(const vol::ChannelGrid& colours) {
  const vol::Dims d = colours.dims();
  const std::string header = std::to_string(d.nx) + "x" + std::to_string(d.ny) + "x" +
                             std::to_string(d.nz) + "x" + std::to_string(colours.channels()) + ":";
  const auto values = colours.data();
  return hex64(
      fnv1a64(std::string_view(reinterpret_cast<const char*>(values.data()), values.size_bytes()),
              fnv1a64(header)));
}

} // namespace

ExemplarSettings read_exemplar_settings(const ConfigSection& section) {
  ExemplarSettings settings;
  settings.key_path = section.path();
  const bool has_file = section.has("file");
  if (has_file && section.has("procedural")) {
    section.fail("procedural", "no procedural generator when exemplar.file is given (one source)");
  }
  if (has_file) {
    for (const char* key : {"size", "seed", "period"}) {
      if (section.has(key)) {
        section.fail(key, std::string("no ") + key + " (only procedural exemplars have one)");
      }
    }
    settings.file = section.require<std::string>("file");
    if (!std::filesystem::is_regular_file(*settings.file)) {
      section.fail("file", "an existing volume file (.vdb, .vti, .h5, .hdf5, .inr)");
    }
    if (!supported_extension(*settings.file)) {
      section.fail("file", "a volume file ending in .vdb, .vti, .h5, .hdf5 or .inr");
    }
  } else {
    std::vector<std::pair<std::string, ProceduralExemplar>> options;
    for (const auto& [name, value] : kGenerators) {
      options.emplace_back(name, value);
    }
    settings.procedural =
        section.choice<ProceduralExemplar>("procedural", settings.procedural, options);
    settings.size = section.get<int>("size", settings.size, int_in_range(kMinSize, kMaxSize));
    settings.seed = section.get<std::uint64_t>("seed", settings.seed);
    if (settings.procedural == ProceduralExemplar::lattice) {
      settings.period = section.get<int>("period", settings.period, int_in_range(1, settings.size));
      if (settings.size % settings.period != 0) {
        section.fail("size", "a multiple of " + section.key_path("period") + " = " +
                                 std::to_string(settings.period) +
                                 " (the lattice tiles whole cells)");
      }
    } else if (section.has("period")) {
      section.fail("period", "no period (only procedural: lattice has one)");
    }
  }
  settings.border = section.choice<ExemplarBorder>(
      "border", settings.border,
      {{"toroidal", ExemplarBorder::toroidal}, {"discard", ExemplarBorder::discard}});
  return settings;
}

Exemplar load_exemplar(const ExemplarSettings& settings) {
  Exemplar exemplar;
  if (settings.file) {
    const std::filesystem::path& path = *settings.file;
    vol::AnyGrid grid;
    try {
      grid = read_grid(path);
    } catch (const InputError& e) {
      TEXSIM_INPUT_ERROR(settings.key_path << ".file: " << e.what());
    }
    exemplar.scalar = std::holds_alternative<vol::ScalarGrid>(grid);
    exemplar.colours = exemplar.scalar ? unit_range_channel(std::get<vol::ScalarGrid>(grid))
                                       : vol::to_channels(std::get<vol::RgbGrid>(grid));
    exemplar.description = "file " + path.string();
  } else {
    exemplar.colours = vol::to_channels(generate(settings));
    exemplar.description = "procedural " + generator_name(settings.procedural) + " " +
                           std::to_string(settings.size) + "^3";
    if (settings.procedural == ProceduralExemplar::lattice) {
      exemplar.description += ", period " + std::to_string(settings.period);
    }
    if (settings.procedural != ProceduralExemplar::stripes) {
      exemplar.description += ", seed " + std::to_string(settings.seed);
    }
  }
  exemplar.content_hash = content_hash(exemplar.colours);
  return exemplar;
}

Exemplar load_exemplar_once_per_node(const par::Comm& comm, const ExemplarSettings& settings) {
  Exemplar loaded;
  par::run_collectively(comm, [&] {
    if (comm.is_root())
      loaded = load_exemplar(settings);
  });
  // dims (3), channels, scalar; then the two strings.
  std::vector<std::int64_t> shape;
  std::vector<char> text;
  if (comm.is_root()) {
    const vol::Dims d = loaded.colours.dims();
    shape = {d.nx, d.ny, d.nz, loaded.colours.channels(), loaded.scalar ? 1 : 0};
    text.assign(loaded.description.begin(), loaded.description.end());
    text.push_back('\0');
    text.insert(text.end(), loaded.content_hash.begin(), loaded.content_hash.end());
  }
  par::broadcast_records(comm, shape);
  par::broadcast_records(comm, text);
  const vol::Dims dims{int(shape[0]), int(shape[1]), int(shape[2])};
  const int channels = int(shape[3]);

  Exemplar exemplar;
  exemplar.scalar = shape[4] != 0;
  const auto split = std::find(text.begin(), text.end(), '\0');
  exemplar.description.assign(text.begin(), split);
  exemplar.content_hash.assign(split + 1, text.end());
  const std::span<const float> values =
      comm.is_root() ? loaded.colours.data() : std::span<const float>();
  exemplar.colours = vol::ChannelGrid(
      dims, channels, par::NodeSharedArray<float>::from_root(par::NodeLayout::make(comm), values));
  return exemplar;
}

void require_exemplar_fits_window(const Exemplar& exemplar, const ExemplarSettings& settings,
                                  int window) {
  const vol::Dims d = exemplar.colours.dims();
  if (std::min({d.nx, d.ny, d.nz}) < 2 * window) {
    TEXSIM_INPUT_ERROR(settings.key_path << ": the exemplar (" << exemplar.description << ") is "
                                         << d.nx << " x " << d.ny << " x " << d.nz
                                         << " voxels, expected at least 2 * window = 2 * " << window
                                         << " = " << 2 * window << " along every axis");
  }
}

} // namespace texsim::pipelines::solid_synthesis
