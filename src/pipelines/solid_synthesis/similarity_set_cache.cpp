#include "pipelines/solid_synthesis/similarity_set_cache.hpp"

#include "pipelines/solid_synthesis/keyed_cache_file.hpp"

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/log.hpp"
#include "io/hdf5_attribute.hpp"
#include "io/hdf5_file.hpp"
#include "io/hdf5_slab.hpp"
#include "par/hdf5_call.hpp"
#include "par/hdf5_handle.hpp"
#include "par/node_shared_array.hpp"

#include <hdf5.h>
#include <mpi.h>

#include <array>
#include <cstdio>
#include <optional>
#include <span>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

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

/// The candidates dataset of the open cache file `h5` when it is [nz, ny, nx, k] as `expected`
/// says; nothing otherwise. May throw for a damaged file. Not collective.
std::optional<par::Hdf5Handle> open_candidates(hid_t h5, const std::filesystem::path& file,
                                               const KeyFields& expected) {
  par::Hdf5Handle data(TEXSIM_HDF5_CALL(H5Dopen2(h5, kDataset, H5P_DEFAULT), file.string()),
                       H5Dclose);
  const vol::Dims dims = expected.dims;
  if (io::dataset_shape(data.get(), file.string()) !=
      std::vector<hsize_t>{static_cast<hsize_t>(dims.nz), static_cast<hsize_t>(dims.ny),
                           static_cast<hsize_t>(dims.nx), static_cast<hsize_t>(expected.options.k)})
    return std::nullopt;
  return data;
}

/// Planes [z_begin, z_end) of the candidates into `out`; false when a set lacks the structure
/// every valid set has (C_1(v) = v, indices inside the grid). May throw for a damaged file.
bool read_candidate_planes(hid_t data, const std::filesystem::path& file, const KeyFields& fields,
                           int z_begin, int z_end, std::span<std::int32_t> out) {
  io::read_leading_slab(data, static_cast<std::uint64_t>(z_begin),
                        static_cast<std::uint64_t>(z_end), out, file.string());
  const int k = fields.options.k;
  const auto voxels = static_cast<std::int64_t>(fields.dims.count());
  const std::int64_t first =
      std::int64_t{z_begin} * std::int64_t{fields.dims.nx} * std::int64_t{fields.dims.ny};
  for (std::size_t at = 0; at < out.size(); ++at) {
    const std::int32_t c = out[at];
    const bool first_of_set = at % static_cast<std::size_t>(k) == 0;
    if (c < 0 || c >= voxels ||
        (first_of_set && c != first + static_cast<std::int64_t>(at / static_cast<std::size_t>(k))))
      return false;
  }
  return true;
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
  // Opens the file and its candidates; nothing for a missing, foreign or misshapen file.
  const auto open = [&]() -> std::optional<std::pair<par::Hdf5Handle, par::Hdf5Handle>> {
    try {
      std::optional<par::Hdf5Handle> h5 = open_cache_file(file, key, kFormatVersion);
      if (!h5)
        return std::nullopt;
      std::optional<par::Hdf5Handle> data = open_candidates(h5->get(), file, fields);
      if (!data)
        return std::nullopt;
      return std::pair{std::move(*h5), std::move(*data)};
    } catch (const std::exception&) {
      return std::nullopt; // damaged: the caller recomputes and overwrites it
    }
  };
  int found = comm.is_root() && open().has_value();
  MPI_Bcast(&found, 1, MPI_INT, 0, comm.raw);
  if (!found)
    return std::nullopt;
  // Every rank reads (and checks) a share of the planes straight into its node's copy.
  const auto opened = open();
  bool failed = !opened;
  const vol::Dims dims = fields.dims;
  const std::size_t plane = static_cast<std::size_t>(dims.nx) * static_cast<std::size_t>(dims.ny) *
                            static_cast<std::size_t>(fields.options.k);
  auto candidates = par::NodeSharedArray<std::int32_t>::filled(
      par::NodeLayout::make(comm), plane * static_cast<std::size_t>(dims.nz),
      [&](std::span<std::int32_t> all, std::size_t begin, std::size_t end) {
        if (failed)
          return;
        try {
          failed = !read_candidate_planes(
              opened->second.get(), file, fields, static_cast<int>(begin / plane),
              static_cast<int>(end / plane), all.subspan(begin, end - begin));
        } catch (const std::exception&) {
          failed = true;
        }
      },
      plane);
  int any_failed = failed;
  MPI_Allreduce(MPI_IN_PLACE, &any_failed, 1, MPI_INT, MPI_MAX, comm.raw);
  if (any_failed)
    return std::nullopt;
  return SimilaritySets{dims, fields.options.k, std::move(candidates)};
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
