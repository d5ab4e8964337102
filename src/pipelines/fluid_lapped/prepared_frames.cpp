#include "pipelines/fluid_lapped/prepared_frames.hpp"

#include "core/error.hpp"
#include "par/collective.hpp"

#include <mpi.h>

#include <cstring>

namespace texsim::pipelines::fluid_lapped {
namespace {

/// Appends the bytes of a vector of trivially copyable values, its length first.
template <typename T> void put(std::vector<char>& bytes, const std::vector<T>& values) {
  const std::uint64_t n = values.size();
  bytes.insert(bytes.end(), reinterpret_cast<const char*>(&n),
               reinterpret_cast<const char*>(&n + 1));
  bytes.insert(bytes.end(), reinterpret_cast<const char*>(values.data()),
               reinterpret_cast<const char*>(values.data() + n));
}

template <typename T> void put_value(std::vector<char>& bytes, const T& value) {
  bytes.insert(bytes.end(), reinterpret_cast<const char*>(&value),
               reinterpret_cast<const char*>(&value + 1));
}

/// Reads what put() wrote, advancing `at`.
template <typename T> std::vector<T> take(const std::vector<char>& bytes, std::size_t& at) {
  std::uint64_t n = 0;
  std::memcpy(&n, bytes.data() + at, sizeof n);
  at += sizeof n;
  std::vector<T> values(n);
  // Eigen's fixed-size vectors (and arrays of them) are plain doubles; their user-declared
  // assignment is what makes GCC ask for copy-assignment instead.
  std::memcpy(static_cast<void*>(values.data()), bytes.data() + at, n * sizeof(T));
  at += n * sizeof(T);
  return values;
}

template <typename T> T take_value(const std::vector<char>& bytes, std::size_t& at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof value);
  at += sizeof value;
  return value;
}

std::vector<char> serialize(const PreparedFrame& prepared) {
  std::vector<char> bytes;
  put_value(bytes, prepared.frame.time);
  put(bytes, prepared.frame.mesh.positions);
  put(bytes, prepared.frame.mesh.triangles);
  put(bytes, prepared.frame.vertex_velocity);
  const auto& atlas = prepared.atlas;
  put_value(bytes, atlas.resolution);
  put_value(bytes, atlas.gutter);
  put_value(bytes, atlas.chart_count);
  put_value(bytes, atlas.texels_per_unit);
  put(bytes, atlas.corner_uv);
  put(bytes, atlas.chart_of_triangle);
  return bytes;
}

PreparedFrame deserialize(const std::vector<char>& bytes) {
  PreparedFrame prepared;
  std::size_t at = 0;
  prepared.frame.time = take_value<double>(bytes, at);
  prepared.frame.mesh.positions = take<geom::Vec3>(bytes, at);
  prepared.frame.mesh.triangles = take<geom::Triangle>(bytes, at);
  prepared.frame.vertex_velocity = take<geom::Vec3>(bytes, at);
  auto& atlas = prepared.atlas;
  atlas.resolution = take_value<int>(bytes, at);
  atlas.gutter = take_value<int>(bytes, at);
  atlas.chart_count = take_value<std::int32_t>(bytes, at);
  atlas.texels_per_unit = take_value<double>(bytes, at);
  atlas.corner_uv = take<std::array<Eigen::Vector2d, 3>>(bytes, at);
  atlas.chart_of_triangle = take<std::int32_t>(bytes, at);
  return prepared;
}

} // namespace

geom::TextureAtlas planar_atlas(const geom::TriangleMesh& mesh, int resolution, int gutter) {
  geom::Vec3 lo = mesh.positions.front(), hi = lo;
  for (const auto& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double side = hi.x() - lo.x();
  if (hi.z() - lo.z() > 1e-9 * side || side <= 0 ||
      std::abs((hi.y() - lo.y()) - side) > 1e-9 * side)
    throw InputError(
        "fluid_lapped.atlas.layout: planar needs a flat square surface in a plane z = const "
        "(the extent is " +
        std::to_string(hi.x() - lo.x()) + " x " + std::to_string(hi.y() - lo.y()) + " x " +
        std::to_string(hi.z() - lo.z()) + "); use layout: charts");
  geom::TextureAtlas atlas;
  atlas.resolution = resolution;
  atlas.gutter = gutter;
  atlas.chart_count = 1;
  atlas.texels_per_unit = resolution / side;
  atlas.chart_of_triangle.assign(mesh.triangles.size(), 0);
  for (const auto& t : mesh.triangles) {
    std::array<Eigen::Vector2d, 3> uv;
    for (int c = 0; c < 3; ++c) {
      const auto& p = mesh.positions[std::size_t(t[std::size_t(c)])];
      uv[std::size_t(c)] = Eigen::Vector2d((p.x() - lo.x()) / side, (p.y() - lo.y()) / side);
    }
    atlas.corner_uv.push_back(uv);
  }
  return atlas;
}

geom::TextureAtlas frame_atlas(const geom::TriangleMesh& mesh, const AtlasSettings& settings) {
  if (settings.layout == AtlasLayout::planar)
    return planar_atlas(mesh, settings.resolution, settings.gutter);
  geom::AtlasSettings atlas;
  atlas.resolution = settings.resolution;
  atlas.gutter = settings.gutter;
  atlas.max_chart_triangles = settings.max_chart_triangles;
  atlas.max_normal_deviation_degrees = settings.max_normal_deviation_degrees;
  return geom::build_texture_atlas(mesh, atlas);
}

PreparedFrames::PreparedFrames(const par::Comm& comm, int frame_count,
                               std::function<FluidFrame(int)> read, AtlasSettings atlas)
    : comm_(comm), frame_count_(frame_count), read_(std::move(read)), atlas_(atlas) {}

PreparedFrame PreparedFrames::get(int k) {
  TEXSIM_VERIFY(k >= 0 && k < frame_count_, "frame " << k << " outside 0.." << frame_count_ - 1);
  if (batch_begin_ < 0 || k >= batch_begin_ + comm_.size || k < batch_begin_) {
    batch_begin_ = k;
    mine_.reset();
    const int mine = k + comm_.rank;
    par::run_collectively(comm_, [&] {
      if (mine < frame_count_) {
        PreparedFrame prepared;
        prepared.frame = read_(mine);
        prepared.atlas = frame_atlas(prepared.frame.mesh, atlas_);
        mine_ = std::move(prepared);
      }
    });
  }
  const int owner = k - batch_begin_;
  std::vector<char> bytes;
  if (comm_.rank == owner)
    bytes = serialize(*mine_);
  std::uint64_t size = bytes.size();
  MPI_Bcast(&size, 1, MPI_UINT64_T, owner, comm_.raw);
  TEXSIM_VERIFY(size < std::uint64_t(INT32_MAX), "frame " << k << " above 2 GiB to broadcast");
  bytes.resize(size);
  MPI_Bcast(bytes.data(), int(size), MPI_BYTE, owner, comm_.raw);
  return deserialize(bytes);
}

} // namespace texsim::pipelines::fluid_lapped
