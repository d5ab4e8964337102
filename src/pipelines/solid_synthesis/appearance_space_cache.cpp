#include "pipelines/solid_synthesis/appearance_space_cache.hpp"

#include "pipelines/solid_synthesis/keyed_cache_file.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "io/hdf5_attribute.hpp"
#include "io/hdf5_file.hpp"
#include "io/hdf5_scalar_type.hpp"
#include "io/hdf5_slab.hpp"
#include "io/scalar_type.hpp"
#include "par/hdf5_call.hpp"
#include "par/hdf5_handle.hpp"
#include "par/node_shared_array.hpp"
#include "vol/node_shared_grid.hpp"

#include <hdf5.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Bumped whenever the file layout or what build_appearance_space computes changes; files of
/// another version are rebuilt.
constexpr std::int64_t kFormatVersion = 1;
/// Stack levels beyond this would need exemplars of 2^31 voxels along an axis.
constexpr int kMaxLevels = 31;
/// Bytes per MPI_Bcast: MPI counts are int.
constexpr std::size_t kBroadcastChunk = std::size_t{1} << 30;

using Shape = std::vector<hsize_t>;

const char* border_name(ExemplarBorder border) {
  return border == ExemplarBorder::toroidal ? "toroidal" : "discard";
}

bool is_exemplar_hash(std::string_view hash) {
  return hash.size() == 16 && std::all_of(hash.begin(), hash.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

/// The options a key names.
AppearanceOptions parse_key(const std::string& key) {
  AppearanceOptions options;
  char hash[17] = {};
  char border[9] = {};
  int consumed = 0;
  const int read = std::sscanf(key.c_str(), "%16[0-9a-f]-d%d-w%d-%8[a-z]%n", hash,
                               &options.dimensions, &options.window, border, &consumed);
  const std::string_view border_text(border);
  options.border = border_text == "discard" ? ExemplarBorder::discard : ExemplarBorder::toroidal;
  TEXSIM_VERIFY(read == 4 && consumed == static_cast<int>(key.size()) && is_exemplar_hash(hash) &&
                    options.dimensions >= 1 && options.window >= 1 && options.window % 2 == 1 &&
                    border_text == border_name(options.border),
                "appearance cache: '" << key << "' is not a key made by appearance_cache_key");
  return options;
}

Shape grid_shape(const vol::ChannelGrid& grid) {
  const vol::Dims dims = grid.dims();
  return {static_cast<hsize_t>(dims.nz), static_cast<hsize_t>(dims.ny),
          static_cast<hsize_t>(dims.nx), static_cast<hsize_t>(grid.channels())};
}

/// Length of a level's neighbourhood vectors: window^3 taps of `channels` values.
Eigen::Index neighbourhood_components(const AppearanceOptions& options, int channels) {
  return static_cast<Eigen::Index>(options.window) * options.window * options.window * channels;
}

/// Whether `space` has the structure build_appearance_space gives for `options`: one level per
/// stack grid with spacing 2^s, every grid on the working exemplar's voxels, `dimensions` features
/// per voxel, a window^3 C mean and a (window^3 C) x dimensions basis.
bool fits_options(const AppearanceSpace& space, const AppearanceOptions& options) {
  const std::size_t level_count = space.levels.size();
  if (level_count < 1 || level_count > kMaxLevels || space.stack.size() != level_count ||
      space.periodic != (options.border == ExemplarBorder::toroidal))
    return false;
  const vol::Dims dims = space.colours.dims();
  const int channels = space.colours.channels();
  const Eigen::Index components = neighbourhood_components(options, channels);
  for (std::size_t s = 0; s < level_count; ++s) {
    const AppearanceLevel& level = space.levels[s];
    const vol::ChannelGrid& stack = space.stack[s];
    if (level.spacing != 1 << s || level.window != options.window || stack.dims() != dims ||
        stack.channels() != channels || level.features.dims() != dims ||
        level.features.channels() != options.dimensions || level.mean.size() != components ||
        level.basis.rows() != components || level.basis.cols() != options.dimensions)
      return false;
  }
  return true;
}

/// Every array of `space` but the grids (node-shared, read plane by plane on every node), in a
/// fixed order, as bytes: what rank 0 broadcasts after reading.
std::vector<std::span<std::byte>> payload(AppearanceSpace& space) {
  std::vector<std::span<std::byte>> parts;
  for (std::size_t s = 0; s < space.levels.size(); ++s) {
    AppearanceLevel& level = space.levels[s];
    parts.push_back(std::as_writable_bytes(
        std::span(level.mean.data(), static_cast<std::size_t>(level.mean.size()))));
    parts.push_back(std::as_writable_bytes(
        std::span(level.basis.data(), static_cast<std::size_t>(level.basis.size()))));
    parts.push_back(std::as_writable_bytes(std::span(&level.spacing, 1)));
    parts.push_back(std::as_writable_bytes(std::span(&level.retained_variance, 1)));
  }
  return parts;
}

/// A zero space shaped like one that fits `options` but without its grids, for the ranks that
/// receive the cached one's statistics (the grids are read node-shared, later).
AppearanceSpace shaped_space(int channels, int level_count, const AppearanceOptions& options) {
  const Eigen::Index components = neighbourhood_components(options, channels);
  AppearanceSpace space;
  space.periodic = options.border == ExemplarBorder::toroidal;
  for (int s = 0; s < level_count; ++s) {
    AppearanceLevel level;
    level.window = options.window;
    level.mean = Eigen::VectorXd::Zero(components);
    level.basis = Eigen::MatrixXd::Zero(components, options.dimensions);
    space.levels.push_back(std::move(level));
  }
  return space;
}

void broadcast_bytes(const par::Comm& comm, std::span<std::byte> bytes) {
  for (std::size_t at = 0; at < bytes.size(); at += kBroadcastChunk)
    MPI_Bcast(bytes.data() + at, static_cast<int>(std::min(kBroadcastChunk, bytes.size() - at)),
              MPI_BYTE, 0, comm.raw);
}

template <class T>
void write_dataset(hid_t parent, const char* name, const Shape& shape, std::span<const T> values,
                   const std::string& where) {
  Shape chunk = shape; // a z-plane of a grid, a column of the basis, the whole mean
  if (chunk.size() > 1)
    chunk.front() = 1;
  const par::Hdf5Handle creation(TEXSIM_HDF5_CALL(H5Pcreate(H5P_DATASET_CREATE), where), H5Pclose);
  TEXSIM_HDF5_CALL(H5Pset_chunk(creation.get(), static_cast<int>(chunk.size()), chunk.data()),
                   where << ": " << name);
  TEXSIM_HDF5_CALL(H5Pset_fletcher32(creation.get()), where << ": " << name);
  const par::Hdf5Handle space(
      TEXSIM_HDF5_CALL(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr),
                       where << ": " << name),
      H5Sclose);
  const hid_t type = io::native_hdf5_type(io::scalar_type_of<T>());
  const par::Hdf5Handle data(TEXSIM_HDF5_CALL(H5Dcreate2(parent, name, type, space.get(),
                                                         H5P_DEFAULT, creation.get(), H5P_DEFAULT),
                                              where << ": dataset " << name),
                             H5Dclose);
  TEXSIM_HDF5_CALL(H5Dwrite(data.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
                   where << ": dataset " << name);
}

/// A [n] dataset as a vector, or an [n, m] dataset as the m x n column-major matrix.
Eigen::MatrixXd read_matrix(hid_t parent, const char* name, const std::string& where) {
  const std::string context = where + ": dataset " + name;
  const par::Hdf5Handle dataset(TEXSIM_HDF5_CALL(H5Dopen2(parent, name, H5P_DEFAULT), context),
                                H5Dclose);
  const Shape shape = io::dataset_shape(dataset.get(), context);
  TEXSIM_VERIFY(shape.size() == 1 || shape.size() == 2, context << " is not 1-D or 2-D");
  const auto rows = static_cast<Eigen::Index>(shape.back());
  const auto cols = static_cast<Eigen::Index>(shape.size() == 2 ? shape[0] : 1);
  Eigen::MatrixXd matrix(rows, cols);
  io::read_leading_slab(dataset.get(), 0, shape[0],
                        std::span(matrix.data(), static_cast<std::size_t>(matrix.size())), context);
  return matrix;
}

std::string level_group(std::size_t s) {
  return "level_" + std::to_string(s);
}

/// Whether the grid dataset `name` of `parent` is [nz, ny, nx, channels].
bool has_grid_shape(hid_t parent, const std::string& name, vol::Dims dims, int channels,
                    const std::string& where) {
  const par::Hdf5Handle dataset(
      TEXSIM_HDF5_CALL(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), where << ": dataset " << name),
      H5Dclose);
  return io::dataset_shape(dataset.get(), where + ": dataset " + name) ==
         Shape{static_cast<hsize_t>(dims.nz), static_cast<hsize_t>(dims.ny),
               static_cast<hsize_t>(dims.nx), static_cast<hsize_t>(channels)};
}

/// What `file` holds besides its grids (levels, statistics and principal axes, the working
/// exemplar's dims and channels) if everything checks out, the grids' shapes included; nothing for
/// a missing, foreign, damaged or inconsistent file. The grids are not read. Not collective.
std::optional<std::pair<AppearanceSpace, Shape>> read_structure(const std::filesystem::path& file,
                                                                const std::string& key,
                                                                const AppearanceOptions& options) {
  try {
    const std::optional<par::Hdf5Handle> h5 = open_cache_file(file, key, kFormatVersion);
    if (!h5)
      return std::nullopt;
    const auto level_count = std::get<std::int64_t>(io::read_attribute(h5->get(), "levels", file));
    if (level_count < 1 || level_count > kMaxLevels)
      return std::nullopt;
    const par::Hdf5Handle colours(
        TEXSIM_HDF5_CALL(H5Dopen2(h5->get(), "colours", H5P_DEFAULT), file.string()), H5Dclose);
    const Shape shape = io::dataset_shape(colours.get(), file.string() + ": dataset colours");
    if (shape.size() != 4 || shape[3] < 1)
      return std::nullopt;
    const vol::Dims dims{static_cast<int>(shape[2]), static_cast<int>(shape[1]),
                         static_cast<int>(shape[0])};
    const int channels = static_cast<int>(shape[3]);
    AppearanceSpace space = shaped_space(channels, static_cast<int>(level_count), options);
    space.periodic = std::get<std::int64_t>(io::read_attribute(h5->get(), "periodic", file)) != 0;
    for (std::size_t s = 0; s < static_cast<std::size_t>(level_count); ++s) {
      const std::string where = file.string() + ": " + level_group(s);
      const par::Hdf5Handle group(
          TEXSIM_HDF5_CALL(H5Gopen2(h5->get(), level_group(s).c_str(), H5P_DEFAULT), where),
          H5Gclose);
      AppearanceLevel& level = space.levels[s];
      level.spacing = static_cast<int>(
          std::get<std::int64_t>(io::read_attribute(group.get(), "spacing", file)));
      level.window =
          static_cast<int>(std::get<std::int64_t>(io::read_attribute(group.get(), "window", file)));
      level.retained_variance =
          std::get<double>(io::read_attribute(group.get(), "retained_variance", file));
      const Eigen::MatrixXd mean = read_matrix(group.get(), "mean", where);
      if (mean.cols() != 1)
        return std::nullopt;
      level.mean = mean.col(0);
      level.basis = read_matrix(group.get(), "basis", where);
      if (!has_grid_shape(group.get(), "stack", dims, channels, where) ||
          !has_grid_shape(group.get(), "features", dims, options.dimensions, where) ||
          level.spacing != 1 << s || level.window != options.window ||
          level.mean.size() != neighbourhood_components(options, channels) ||
          level.basis.rows() != level.mean.size() || level.basis.cols() != options.dimensions)
        return std::nullopt;
    }
    if (space.periodic != (options.border == ExemplarBorder::toroidal))
      return std::nullopt;
    return std::pair{std::move(space), shape};
  } catch (const std::exception&) {
    return std::nullopt; // damaged: the caller rebuilds and overwrites it
  }
}

/// The grids of the cache file `h5` (known to have the shapes of `space`'s colours), each held
/// once per node: every rank reads a share of the planes of each. `failed` is set on a rank whose
/// reads failed (a damaged chunk). Collective over layout->world.
void read_grids(const std::shared_ptr<const par::NodeLayout>& layout, hid_t h5,
                const std::filesystem::path& file, vol::Dims dims, int channels,
                const AppearanceOptions& options, AppearanceSpace& space, bool& failed) {
  const auto read = [&](const std::string& name, int grid_channels) {
    return vol::node_shared_grid(
        layout, dims, grid_channels, [&](int z_begin, int z_end, std::span<float> out) {
          if (failed)
            return;
          try {
            const std::string where = file.string() + ": dataset " + name;
            const par::Hdf5Handle dataset(
                TEXSIM_HDF5_CALL(H5Dopen2(h5, name.c_str(), H5P_DEFAULT), where), H5Dclose);
            io::read_leading_slab(dataset.get(), static_cast<std::uint64_t>(z_begin),
                                  static_cast<std::uint64_t>(z_end), out, where);
          } catch (const std::exception&) {
            failed = true;
          }
        });
  };
  space.colours = read("colours", channels);
  for (std::size_t s = 0; s < space.levels.size(); ++s) {
    space.stack.push_back(read(level_group(s) + "/stack", channels));
    space.levels[s].features = read(level_group(s) + "/features", options.dimensions);
  }
}

void write_space(const std::filesystem::path& file, const std::string& key,
                 const AppearanceSpace& space) {
  write_cache_file(file, key, kFormatVersion, [&](hid_t h5, const std::filesystem::path& path) {
    const std::string context = path.string();
    write_dataset<float>(h5, "colours", grid_shape(space.colours), space.colours.data(), context);
    for (std::size_t s = 0; s < space.levels.size(); ++s) {
      const AppearanceLevel& level = space.levels[s];
      const std::string where = context + ": " + level_group(s);
      const par::Hdf5Handle group(
          TEXSIM_HDF5_CALL(
              H5Gcreate2(h5, level_group(s).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), where),
          H5Gclose);
      write_dataset<float>(group.get(), "stack", grid_shape(space.stack[s]), space.stack[s].data(),
                           where);
      write_dataset<float>(group.get(), "features", grid_shape(level.features),
                           level.features.data(), where);
      const auto components = static_cast<hsize_t>(level.mean.size());
      write_dataset<double>(group.get(), "mean", {components},
                            std::span(level.mean.data(), components), where);
      write_dataset<double>(
          group.get(), "basis", {static_cast<hsize_t>(level.basis.cols()), components},
          std::span(level.basis.data(), static_cast<std::size_t>(level.basis.size())), where);
      io::write_attribute(group.get(), "spacing", std::int64_t{level.spacing}, path);
      io::write_attribute(group.get(), "window", std::int64_t{level.window}, path);
      io::write_attribute(group.get(), "retained_variance", level.retained_variance, path);
    }
    io::write_attribute(h5, "periodic", std::int64_t{space.periodic}, path);
    io::write_attribute(h5, "levels", static_cast<std::int64_t>(space.levels.size()), path);
  });
}

} // namespace

std::string appearance_cache_key(const std::string& exemplar_hash,
                                 const AppearanceOptions& options) {
  TEXSIM_VERIFY(is_exemplar_hash(exemplar_hash), "appearance cache: exemplar hash '"
                                                     << exemplar_hash
                                                     << "' is not 16 lower-case hex digits");
  char text[80];
  std::snprintf(text, sizeof text, "%s-d%d-w%d-%s", exemplar_hash.c_str(), options.dimensions,
                options.window, border_name(options.border));
  return text;
}

std::optional<AppearanceSpace> load_appearance_space(const par::Comm& comm,
                                                     const std::filesystem::path& file,
                                                     const std::string& key) {
  const AppearanceOptions options = parse_key(key);
  std::optional<AppearanceSpace> space;
  // found, nx, ny, nz, channels, levels: rank 0 checks the file's structure and statistics.
  std::array<int, 6> shape{};
  if (comm.is_root()) {
    if (auto structure = read_structure(file, key, options)) {
      const Shape& grid = structure->second;
      shape = {1,
               static_cast<int>(grid[2]),
               static_cast<int>(grid[1]),
               static_cast<int>(grid[0]),
               static_cast<int>(grid[3]),
               static_cast<int>(structure->first.levels.size())};
      space = std::move(structure->first);
    }
  }
  MPI_Bcast(shape.data(), static_cast<int>(shape.size()), MPI_INT, 0, comm.raw);
  if (shape[0] == 0)
    return std::nullopt;
  if (!comm.is_root())
    space = shaped_space(shape[4], shape[5], options);
  for (const std::span<std::byte> part : payload(*space))
    broadcast_bytes(comm, part);
  // The grids: every rank reads its share of each straight into its node's copy.
  bool failed = false;
  {
    std::optional<par::Hdf5Handle> h5;
    try {
      h5 = open_cache_file(file, key, kFormatVersion);
    } catch (const std::exception&) {
    }
    failed = !h5;
    read_grids(par::NodeLayout::make(comm), h5 ? h5->get() : H5I_INVALID_HID, file,
               {shape[1], shape[2], shape[3]}, shape[4], options, *space, failed);
  }
  int any_failed = failed;
  MPI_Allreduce(MPI_IN_PLACE, &any_failed, 1, MPI_INT, MPI_MAX, comm.raw);
  if (any_failed || !fits_options(*space, options))
    return std::nullopt;
  return space;
}

void save_appearance_space(const par::Comm& comm, const std::filesystem::path& file,
                           const std::string& key, const AppearanceSpace& space) {
  TEXSIM_VERIFY(fits_options(space, parse_key(key)),
                "appearance cache: the appearance space does not have the structure key "
                    << key << " names");
  if (comm.is_root()) {
    try {
      write_space(file, key, space);
    } catch (const std::exception& e) {
      log::warn(log::cat("appearance cache not written (", file.string(), "): ", e.what()));
    }
  }
  MPI_Barrier(comm.raw);
}

} // namespace texsim::pipelines::solid_synthesis
