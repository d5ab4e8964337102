#include "vol/vdb_io.hpp"

#include "core/atomic_output.hpp"
#include "core/input_file.hpp"
#include "vol/grid_checks.hpp"
#include "vol/vdb_grid_description.hpp"

#include <algorithm>
#include <mutex>
#include <sstream>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/VolumeToMesh.h>

namespace texsim::vol {
namespace {

constexpr const char* kDimsKey = "texsim_dense_dims";
// The transform loses the last bits of the spacing when stored, so the exact values travel as
// metadata too.
constexpr const char* kSpacingKey = "texsim_spacing";
constexpr const char* kOriginKey = "texsim_origin";

} // namespace

void initialize_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

void describe_dense_grid(openvdb::GridBase& grid, Dims dims, const std::array<double, 3>& spacing,
                         const std::array<double, 3>& origin, const std::string& grid_name) {
  const openvdb::Vec3d s(spacing[0], spacing[1], spacing[2]), o(origin[0], origin[1], origin[2]);
  grid.setName(grid_name);
  grid.setTransform(std::make_shared<openvdb::math::Transform>(
      std::make_shared<openvdb::math::ScaleTranslateMap>(s, o)));
  grid.insertMeta(kDimsKey, openvdb::Vec3IMetadata(openvdb::Vec3i(dims.nx, dims.ny, dims.nz)));
  grid.insertMeta(kSpacingKey, openvdb::Vec3DMetadata(s));
  grid.insertMeta(kOriginKey, openvdb::Vec3DMetadata(o));
}

namespace {

openvdb::Vec3s to_vdb(const img::Rgb& c) {
  return {c.r, c.g, c.b};
}
float to_vdb(float v) {
  return v;
}
void from_vdb(const openvdb::Vec3s& v, img::Rgb& c) {
  c = {v.x(), v.y(), v.z()};
}
void from_vdb(float v, float& out) {
  out = v;
}

/// Describes `vdb` as a dense grid of `dims` voxels, spacing `s` and origin `o`, and writes it
/// as the only grid of the file at `path`, atomically.
template <class VdbGrid>
void write_dense_grid_file(const std::filesystem::path& path, VdbGrid& vdb, Dims dims,
                           const std::array<double, 3>& s, const std::array<double, 3>& o,
                           const std::string& grid_name) {
  describe_dense_grid(vdb, dims, s, o, grid_name);
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    try {
      openvdb::io::File file(temporary.string());
      file.write(openvdb::GridCPtrVec{vdb.copy()});
      file.close();
    } catch (const openvdb::Exception& e) {
      TEXSIM_VERIFY(false, path.string() << ": cannot write OpenVDB file: " << e.what());
    }
  });
}

/// Sets the voxels of `vdb`, a volume of `dims`, to value_of(v), v counted x fastest; voxels
/// equal to the background stay inactive.
template <class VdbGrid, class ValueOf>
void copy_voxels(VdbGrid& vdb, Dims dims, const ValueOf& value_of) {
  using ValueT = typename VdbGrid::ValueType;
  const openvdb::CoordBBox box(openvdb::Coord(0, 0, 0),
                               openvdb::Coord(dims.nx - 1, dims.ny - 1, dims.nz - 1));
  openvdb::tools::Dense<ValueT, openvdb::tools::LayoutXYZ> dense(box);
  for (std::size_t v = 0; v < dims.count(); ++v)
    dense.data()[v] = value_of(v);
  openvdb::tools::copyFromDense(dense, vdb, openvdb::zeroVal<ValueT>());
}

/// A .vdb of one grid of `dims` voxels whose voxel v (x fastest) is value_of(v).
template <class VdbGrid, class ValueOf>
void write_grid(const std::filesystem::path& path, Dims dims, const std::array<double, 3>& s,
                const std::array<double, 3>& o, const ValueOf& value_of,
                const std::string& grid_name) {
  initialize_openvdb();
  auto vdb = VdbGrid::create(openvdb::zeroVal<typename VdbGrid::ValueType>());
  copy_voxels(*vdb, dims, value_of);
  write_dense_grid_file(path, *vdb, dims, s, o, grid_name);
}

template <class VdbGrid, class T>
void write_grid(const std::filesystem::path& path, const DenseGrid<T>& grid,
                const std::string& grid_name) {
  const auto values = grid.data();
  write_grid<VdbGrid>(
      path, grid.dims(), grid.spacing(), grid.origin(),
      [&](std::size_t v) { return to_vdb(values[v]); }, grid_name);
}

template <class VdbGrid, class T>
DenseGrid<T> to_dense(const VdbGrid& vdb, const std::filesystem::path& path) {
  using ValueT = typename VdbGrid::ValueType;
  openvdb::CoordBBox box;
  if (const auto meta = vdb.template getMetadata<openvdb::Vec3IMetadata>(kDimsKey)) {
    const openvdb::Vec3i n = meta->value();
    require_grid_fits(path, n.x(), n.y(), n.z(), sizeof(ValueT));
    box = openvdb::CoordBBox(openvdb::Coord(0, 0, 0),
                             openvdb::Coord(n.x() - 1, n.y() - 1, n.z() - 1));
  } else {
    box = vdb.evalActiveVoxelBoundingBox();
  }
  if (box.empty()) {
    TEXSIM_INPUT_ERROR(path.string() << ": grid '" << vdb.getName()
                                     << "' has no active voxels, expected a non-empty volume");
  }
  const openvdb::math::Transform& transform = vdb.transform();
  if (!transform.isLinear() || !transform.baseMap()->getAffineMap()->isScaleTranslate()) {
    TEXSIM_INPUT_ERROR(path.string()
                       << ": grid '" << vdb.getName() << "' has a " << transform.mapType()
                       << " transform, expected an axis-aligned scale and translation");
  }
  const auto edge = [&](int axis) {
    return std::int64_t(box.max()[axis]) - std::int64_t(box.min()[axis]) + 1;
  };
  require_grid_fits(path, edge(0), edge(1), edge(2), sizeof(ValueT));
  openvdb::tools::Dense<ValueT, openvdb::tools::LayoutXYZ> dense(box);
  openvdb::tools::copyToDense(vdb, dense);
  const openvdb::Coord size = box.dim();
  DenseGrid<T> grid(Dims{size.x(), size.y(), size.z()});
  std::transform(dense.data(), dense.data() + grid.size(), grid.data().begin(),
                 [](const ValueT& v) {
                   T out;
                   from_vdb(v, out);
                   return out;
                 });
  const auto exact_spacing = vdb.template getMetadata<openvdb::Vec3DMetadata>(kSpacingKey);
  const auto exact_origin = vdb.template getMetadata<openvdb::Vec3DMetadata>(kOriginKey);
  const openvdb::Vec3d spacing = exact_spacing ? exact_spacing->value() : transform.voxelSize();
  const openvdb::Vec3d origin =
      exact_origin ? exact_origin->value() : transform.indexToWorld(box.min());
  grid.set_spacing({spacing.x(), spacing.y(), spacing.z()});
  grid.set_origin({origin.x(), origin.y(), origin.z()});
  return grid;
}

} // namespace

void write_vdb(const std::filesystem::path& path, const ScalarGrid& grid,
               const std::string& grid_name) {
  write_grid<openvdb::FloatGrid>(path, grid, grid_name);
}

void write_vdb(const std::filesystem::path& path, const RgbGrid& grid,
               const std::string& grid_name) {
  write_grid<openvdb::Vec3SGrid>(path, grid, grid_name);
}

void write_vdb(const std::filesystem::path& path, const ChannelGrid& grid,
               const std::string& grid_name) {
  TEXSIM_VERIFY(grid.channels() == 1 || grid.channels() == 3,
                path.string() << ": a .vdb grid of " << grid.channels()
                              << " channels, expected 1 or 3");
  const std::array<double, 3> spacing{1.0, 1.0, 1.0}, origin{0.0, 0.0, 0.0};
  if (grid.channels() == 1)
    write_grid<openvdb::FloatGrid>(
        path, grid.dims(), spacing, origin, [&](std::size_t v) { return grid.voxel(v)[0]; },
        grid_name);
  else
    write_grid<openvdb::Vec3SGrid>(
        path, grid.dims(), spacing, origin,
        [&](std::size_t v) {
          const auto c = grid.voxel(v);
          return openvdb::Vec3s(c[0], c[1], c[2]);
        },
        grid_name);
}

namespace {

/// Grid `grid_name` of a .vdb file (empty: its first FloatGrid or Vec3SGrid); InputError naming
/// the file, the grid and the grids it has when that fails.
openvdb::GridBase::Ptr read_named_grid(const std::filesystem::path& path,
                                       const std::string& grid_name) {
  initialize_openvdb();
  require_regular_file(path, "OpenVDB file (.vdb)");
  openvdb::GridBase::Ptr base;
  std::ostringstream available;
  try {
    openvdb::io::File file(path.string());
    file.open();
    std::string chosen = grid_name;
    for (auto name = file.beginName(); name != file.endName(); ++name) {
      available << (available.tellp() > 0 ? ", " : "") << "'" << name.gridName() << "'";
    }
    if (chosen.empty()) {
      const openvdb::GridPtrVecPtr grids = file.readAllGridMetadata();
      for (const auto& grid : *grids) {
        if (grid->isType<openvdb::FloatGrid>() || grid->isType<openvdb::Vec3SGrid>()) {
          chosen = grid->getName();
          break;
        }
      }
      if (chosen.empty()) {
        TEXSIM_INPUT_ERROR(path.string() << ": no FloatGrid or Vec3SGrid in the file, it has "
                                         << (available.tellp() > 0 ? available.str() : "no grids"));
      }
    }
    if (!file.hasGrid(chosen)) {
      TEXSIM_INPUT_ERROR(path.string() << ": no grid named '" << chosen << "', the file has "
                                       << (available.tellp() > 0 ? available.str() : "no grids"));
    }
    base = file.readGrid(chosen);
    file.close();
  } catch (const openvdb::Exception& e) {
    TEXSIM_INPUT_ERROR(path.string() << ": not a readable OpenVDB file: " << e.what());
  } catch (const std::ios_base::failure& e) {
    TEXSIM_INPUT_ERROR(path.string() << ": not a readable OpenVDB file: " << e.what());
  }
  return base;
}

} // namespace

AnyGrid read_vdb(const std::filesystem::path& path, const std::string& grid_name) {
  const auto base = read_named_grid(path, grid_name);
  if (auto scalar = openvdb::gridPtrCast<openvdb::FloatGrid>(base)) {
    return with_finite_voxels(path, to_dense<openvdb::FloatGrid, float>(*scalar, path));
  }
  if (auto colour = openvdb::gridPtrCast<openvdb::Vec3SGrid>(base)) {
    return with_finite_voxels(path, to_dense<openvdb::Vec3SGrid, img::Rgb>(*colour, path));
  }
  TEXSIM_INPUT_ERROR(path.string() << ": grid '" << base->getName() << "' is of type "
                                   << base->type() << ", expected a FloatGrid or Vec3SGrid");
}

LevelSetSurface read_level_set_surface(const std::filesystem::path& path,
                                       const std::string& grid_name) {
  const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(read_named_grid(path, grid_name));
  if (!grid)
    TEXSIM_INPUT_ERROR(path.string()
                       << ": grid '" << grid_name << "' is not a FloatGrid; expected a level set");
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*grid, points, triangles, quads, 0.0);
  LevelSetSurface surface;
  for (const auto& p : points)
    surface.positions.push_back({double(p.x()), double(p.y()), double(p.z())});
  const auto add = [&](unsigned a, unsigned b, unsigned c) {
    // volumeToMesh turns faces counter-clockwise around the outward normal of a level set that
    // is negative inside (tests/fluid_lapped/frames_test.cpp checks the enclosed volume's sign).
    surface.triangles.push_back({std::int32_t(a), std::int32_t(b), std::int32_t(c)});
  };
  for (const auto& t : triangles)
    add(t[0], t[1], t[2]);
  for (const auto& q : quads) { // split along the 0-2 diagonal, the same for every quad
    add(q[0], q[1], q[2]);
    add(q[0], q[2], q[3]);
  }
  if (surface.triangles.empty())
    TEXSIM_INPUT_ERROR(path.string() << ": level set '" << grid->getName()
                                     << "' has no zero crossing (no surface)");
  return surface;
}

} // namespace texsim::vol
