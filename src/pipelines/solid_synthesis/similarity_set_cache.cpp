#include "pipelines/solid_synthesis/similarity_set_cache.hpp"

#include "pipelines/solid_synthesis/keyed_cache_file.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/log.hpp"
#include "io/hdf5_attribute.hpp"
#include "io/hdf5_file.hpp"
#include "par/hdf5_call.hpp"
#include "par/hdf5_handle.hpp"

#include <hdf5.h>
#include <mpi.h>

#include <array>
#include <cstdio>
#include <string_view>
#include <system_error>

namespace texsim::pipelines::solid_synthesis {
namespace {

/// Bumped whenever the file layout changes; files of another version are recomputed.
constexpr std::int64_t kFormatVersion = 1;
constexpr const char* kDataset = "candidates";

/// What a key says about the sets it names.
struct KeyFields {
  vol::Dims dims;
  int channels = 0;
  SimilarityOptions options;
};

std::string format_key(const KeyFields& f, std::uint64_t feature_hash) {
  char text[160];
  std::snprintf(text, sizeof text, "%dx%dx%dx%d-k%d-n%d-%s-%s", f.dims.nx, f.dims.ny, f.dims.nz,
                f.channels, f.options.k, f.options.window, f.options.periodic ? "torus" : "open",
                hex64(feature_hash).c_str());
  return text;
}

KeyFields parse_key(const std::string& key) {
  KeyFields f;
  char border[8] = {};
  char hash[17] = {};
  const int read =
      std::sscanf(key.c_str(), "%dx%dx%dx%d-k%d-n%d-%5[a-z]-%16[0-9a-f]", &f.dims.nx, &f.dims.ny,
                  &f.dims.nz, &f.channels, &f.options.k, &f.options.window, border, hash);
  f.options.periodic = std::string_view(border) == "torus";
  TEXSIM_VERIFY(read == 8 && f.options.k >= 1 && f.dims.count() > 0 &&
                    (f.options.periodic || std::string_view(border) == "open"),
                "similarity-set cache: '" << key << "' is not a key made by similarity_cache_key");
  return f;
}

/// The candidates in `file` if everything checks out; nothing for a missing, foreign, damaged or
/// inconsistent file. Not collective.
std::optional<std::vector<std::int32_t>> read_candidates(const std::filesystem::path& file,
                                                         const std::string& key,
                                                         const KeyFields& expected) {
  try {
    const std::optional<par::Hdf5Handle> h5 = open_cache_file(file, key, kFormatVersion);
    if (!h5)
      return std::nullopt;
    const int k = expected.options.k;
    const par::Hdf5Handle data(
        TEXSIM_HDF5_CALL(H5Dopen2(h5->get(), kDataset, H5P_DEFAULT), file.string()), H5Dclose);
    const par::Hdf5Handle space(TEXSIM_HDF5_CALL(H5Dget_space(data.get()), file.string()),
                                H5Sclose);
    std::array<hsize_t, 4> shape{};
    if (TEXSIM_HDF5_CALL(H5Sget_simple_extent_ndims(space.get()), file.string()) != 4)
      return std::nullopt;
    TEXSIM_HDF5_CALL(H5Sget_simple_extent_dims(space.get(), shape.data(), nullptr), file.string());
    const vol::Dims dims = expected.dims;
    if (shape != std::array<hsize_t, 4>{static_cast<hsize_t>(dims.nz),
                                        static_cast<hsize_t>(dims.ny),
                                        static_cast<hsize_t>(dims.nx), static_cast<hsize_t>(k)})
      return std::nullopt;
    std::vector<std::int32_t> candidates(dims.count() * k);
    TEXSIM_HDF5_CALL(
        H5Dread(data.get(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, candidates.data()),
        file.string());
    // Structure every valid set has: C_1(v) = v and indices inside the grid.
    const auto voxels = static_cast<std::int64_t>(dims.count());
    for (std::int64_t v = 0; v < voxels; ++v)
      for (int i = 0; i < k; ++i) {
        const std::int32_t c = candidates[static_cast<std::size_t>(v * k + i)];
        if (c < 0 || c >= voxels || (i == 0 && c != v))
          return std::nullopt;
      }
    return candidates;
  } catch (const std::exception&) {
    return std::nullopt; // damaged: the caller recomputes and overwrites it
  }
}

void write_sets(const std::filesystem::path& file, const std::string& key, const KeyFields& fields,
                const SimilaritySets& sets) {
  write_cache_file(file, key, kFormatVersion, [&](hid_t h5, const std::filesystem::path& path) {
    const std::string context = path.string();
    const std::array<hsize_t, 4> shape{
        static_cast<hsize_t>(sets.dims.nz), static_cast<hsize_t>(sets.dims.ny),
        static_cast<hsize_t>(sets.dims.nx), static_cast<hsize_t>(sets.k)};
    const par::Hdf5Handle space(
        TEXSIM_HDF5_CALL(H5Screate_simple(4, shape.data(), nullptr), context), H5Sclose);
    const par::Hdf5Handle data(TEXSIM_HDF5_CALL(H5Dcreate2(h5, kDataset, H5T_STD_I32LE, space.get(),
                                                           H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                                context << ": dataset " << kDataset),
                               H5Dclose);
    TEXSIM_HDF5_CALL(H5Dwrite(data.get(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                              sets.candidates.data()),
                     context << ": dataset " << kDataset);
    io::write_attribute(h5, "k", std::int64_t{sets.k}, path);
    io::write_attribute(h5, "window", std::int64_t{fields.options.window}, path);
    io::write_attribute(h5, "periodic", std::int64_t{fields.options.periodic}, path);
  });
}

} // namespace

std::string similarity_cache_key(const vol::ChannelGrid& features,
                                 const SimilarityOptions& options) {
  const auto values = features.data();
  const std::string_view bytes(reinterpret_cast<const char*>(values.data()),
                               values.size() * sizeof(float));
  return format_key({features.dims(), features.channels(), options}, fnv1a64(bytes));
}

std::optional<SimilaritySets> load_similarity_sets(const par::Comm& comm,
                                                   const std::filesystem::path& file,
                                                   const std::string& key) {
  const KeyFields fields = parse_key(key);
  std::optional<std::vector<std::int32_t>> candidates;
  if (comm.is_root())
    candidates = read_candidates(file, key, fields);
  int found = candidates.has_value();
  MPI_Bcast(&found, 1, MPI_INT, 0, comm.raw);
  if (!found)
    return std::nullopt;
  const std::span<const std::int32_t> read =
      comm.is_root() ? std::span<const std::int32_t>(*candidates) : std::span<const std::int32_t>();
  return SimilaritySets{
      fields.dims, fields.options.k,
      par::NodeSharedArray<std::int32_t>::from_root(par::NodeLayout::make(comm), read)};
}

void save_similarity_sets(const par::Comm& comm, const std::filesystem::path& file,
                          const std::string& key, const SimilaritySets& sets) {
  const KeyFields fields = parse_key(key);
  TEXSIM_VERIFY(fields.dims == sets.dims && fields.options.k == sets.k &&
                    sets.candidates.size() == sets.dims.count() * static_cast<std::size_t>(sets.k),
                "similarity-set cache: sets of " << sets.dims.nx << " x " << sets.dims.ny << " x "
                                                 << sets.dims.nz << ", k = " << sets.k
                                                 << " do not match key " << key);
  if (comm.is_root()) {
    try {
      write_sets(file, key, fields, sets);
    } catch (const std::exception& e) {
      log::warn(log::cat("similarity-set cache not written (", file.string(), "): ", e.what()));
    }
  }
  MPI_Barrier(comm.raw);
}

} // namespace texsim::pipelines::solid_synthesis
