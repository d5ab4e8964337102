#include "pipelines/fluid_lapped/fluid_frames.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_remesh.hpp"
#include "geom/mesh_validation.hpp"
#include "io/pvd_series.hpp"
#include "vol/trilinear.hpp"
#include "vol/vdb_io.hpp"
#include "vol/vti_io.hpp"

#include <algorithm>
#include <cstdio>

namespace texsim::pipelines::fluid_lapped {
namespace {

constexpr const char* kKey = "fluid_lapped.frames.surfaces";

/// The file name a printf pattern gives for index k.
std::string pattern_name(const std::string& pattern, int k) {
  std::vector<char> name(pattern.size() + 32);
  std::snprintf(name.data(), name.size(), pattern.c_str(), k);
  return name.data();
}

/// A surface with the velocity at its vertices, as stored in the file; a .vdb level set is
/// meshed at its zero crossing.
FluidFrame read_stored(const std::filesystem::path& path, const std::string& velocity_array,
                       const std::string& level_set_grid) {
  FluidFrame frame;
  if (path.extension() == ".vdb") {
    auto surface = vol::read_level_set_surface(path, level_set_grid);
    for (const auto& p : surface.positions)
      frame.mesh.positions.emplace_back(p[0], p[1], p[2]);
    for (const auto& t : surface.triangles)
      frame.mesh.triangles.push_back({t[0], t[1], t[2]});
    if (!velocity_array.empty())
      TEXSIM_INPUT_ERROR(path.string() << ": a level set has no point arrays; give the velocity "
                                          "as fluid_lapped.frames.velocity_grids");
  } else if (velocity_array.empty()) {
    frame.mesh = geom::read_raw_mesh(path);
  } else {
    auto vectors = geom::read_vertex_vectors(path, velocity_array);
    frame.mesh = std::move(vectors.mesh);
    frame.vertex_velocity = std::move(vectors.values);
  }
  return frame;
}

/// The vertex velocity of `frame` at the closest point of its surface to x.
geom::Vec3 velocity_near(const FluidFrame& frame, const geom::AabbTree& tree, const geom::Vec3& x) {
  const auto closest = tree.closest_point(x);
  const auto& t = frame.mesh.triangles[std::size_t(closest.triangle)];
  const auto w = geom::barycentric_weights(frame.mesh.positions[std::size_t(t[0])],
                                           frame.mesh.positions[std::size_t(t[1])],
                                           frame.mesh.positions[std::size_t(t[2])], closest.point);
  geom::Vec3 v = geom::Vec3::Zero();
  for (int c = 0; c < 3; ++c)
    v += w[std::size_t(c)] * frame.vertex_velocity[std::size_t(t[std::size_t(c)])];
  return v;
}

class SurfaceVelocity : public VelocityField {
public:
  SurfaceVelocity(FluidFrame a, FluidFrame b)
      : a_(std::move(a)), b_(std::move(b)), tree_a_(a_.mesh), tree_b_(b_.mesh) {}

  geom::Vec3 at(const geom::Vec3& x, double time) const override {
    const double span = b_.time - a_.time;
    const double s = span > 0 ? std::clamp((time - a_.time) / span, 0.0, 1.0) : 0.0;
    return (1.0 - s) * velocity_near(a_, tree_a_, x) + s * velocity_near(b_, tree_b_, x);
  }

private:
  FluidFrame a_, b_;
  geom::AabbTree tree_a_, tree_b_;
};

class GridVelocity : public VelocityField {
public:
  GridVelocity(vol::RgbGrid a, double t_a, vol::RgbGrid b, double t_b)
      : a_(std::move(a)), b_(std::move(b)), t_a_(t_a), t_b_(t_b) {}

  geom::Vec3 at(const geom::Vec3& x, double time) const override {
    const double span = t_b_ - t_a_;
    const double s = span > 0 ? std::clamp((time - t_a_) / span, 0.0, 1.0) : 0.0;
    return (1.0 - s) * sample(a_, x) + s * sample(b_, x);
  }

private:
  static geom::Vec3 sample(const vol::RgbGrid& grid, const geom::Vec3& x) {
    const auto v = vol::trilinear(grid, vol::voxel_coordinates(grid, {x.x(), x.y(), x.z()}));
    return {v[0], v[1], v[2]};
  }

  vol::RgbGrid a_, b_;
  double t_a_, t_b_;
};

/// The files and times of a .pvd or a printf pattern (times k x interval); InputError naming
/// `key` when the spec is neither or lists nothing.
void list_series(const std::string& spec, double interval, const std::string& key,
                 std::vector<std::filesystem::path>& files, std::vector<double>& times) {
  const std::filesystem::path path = spec;
  if (path.extension() == ".pvd") {
    for (const auto& entry : io::PvdSeries::read_entries(path)) {
      files.push_back(path.parent_path() / entry.file);
      times.push_back(entry.time);
    }
  } else if (spec.find('%') != std::string::npos) {
    const int first = std::filesystem::exists(pattern_name(spec, 0)) ? 0 : 1;
    for (int k = first; std::filesystem::exists(pattern_name(spec, k)); ++k) {
      files.push_back(pattern_name(spec, k));
      times.push_back(k * interval);
    }
  } else {
    TEXSIM_INPUT_ERROR(key << ": '" << spec
                           << "' is neither a .pvd nor a name pattern with a printf integer "
                              "(frames/surface_%04d.vtp)");
  }
  if (files.empty())
    TEXSIM_INPUT_ERROR(key << ": no frame found for '" << spec << "'");
}

} // namespace

FrameSource::FrameSource(FrameSourceSettings settings) : settings_(std::move(settings)) {
  list_series(settings_.frames, settings_.frame_interval, kKey, files_, times_);
  if (!settings_.velocity_grids.empty()) {
    constexpr const char* kGridKey = "fluid_lapped.frames.velocity_grids";
    std::vector<double> grid_times;
    list_series(settings_.velocity_grids, settings_.frame_interval, kGridKey, grid_files_,
                grid_times);
    if (grid_times != times_)
      TEXSIM_INPUT_ERROR(kGridKey << ": " << grid_files_.size() << " grids at other times than the "
                                  << files_.size() << " surfaces of " << settings_.frames
                                  << "; expected one grid per frame at the frame's time");
    for (const auto& file : grid_files_) {
      if (file.extension() != ".vti" && file.extension() != ".vdb")
        TEXSIM_INPUT_ERROR(kGridKey << ": " << file.string()
                                    << " is neither a .vti nor a .vdb vector grid");
      if (!std::filesystem::is_regular_file(file))
        TEXSIM_INPUT_ERROR(kGridKey << ": " << file.string() << " is missing");
    }
  }
  for (std::size_t k = 0; k < files_.size(); ++k) {
    if (!std::filesystem::is_regular_file(files_[k]))
      TEXSIM_INPUT_ERROR(kKey << ": frame " << k << " of " << settings_.frames << ", "
                              << files_[k].string() << ", is missing");
    if (k > 0 && !(times_[k] > times_[k - 1]))
      TEXSIM_INPUT_ERROR(kKey << ": the times of " << settings_.frames << " must increase; frame "
                              << k << " has " << times_[k] << " after " << times_[k - 1]);
  }
  edge_length_ =
      settings_.edge_length > 0
          ? settings_.edge_length
          : geom::mean_edge_length(read_stored(files_.front(), "", settings_.level_set_grid).mesh);
}

vol::RgbGrid FrameSource::velocity_grid(int k) const {
  const auto& file = grid_files_[std::size_t(k)];
  const bool is_vdb = file.extension() == ".vdb";
  // Simulators name the velocity U (OpenFOAM, in .vti via VTK) or vel (Houdini, in .vdb).
  const std::string name =
      !settings_.grid_array.empty() ? settings_.grid_array : (is_vdb ? "vel" : "U");
  auto grid = is_vdb ? vol::read_vdb(file, name) : vol::read_vti(file, name);
  if (!std::holds_alternative<vol::RgbGrid>(grid))
    TEXSIM_INPUT_ERROR(file.string() << ": " << (is_vdb ? "grid" : "array") << " '" << name
                                     << "' has one component; expected a 3-component velocity");
  return std::get<vol::RgbGrid>(std::move(grid));
}

FluidFrame FrameSource::read(int k) const {
  const auto& path = files_[std::size_t(k)];
  auto stored = read_stored(path, settings_.velocity_array, settings_.level_set_grid);
  stored.time = times_[std::size_t(k)];
  auto mesh = stored.mesh;
  geom::MeshRepairOptions repair;
  repair.split_non_manifold = true;
  geom::repair(mesh, repair, path.string());
  FluidFrame frame;
  frame.time = stored.time;
  frame.mesh = geom::remesh_isotropic(mesh, {edge_length_, 3});
  if (!stored.vertex_velocity.empty()) {
    const geom::AabbTree tree(stored.mesh);
    frame.vertex_velocity.resize(frame.mesh.positions.size());
    for (std::size_t v = 0; v < frame.mesh.positions.size(); ++v)
      frame.vertex_velocity[v] = velocity_near(stored, tree, frame.mesh.positions[v]);
  }
  return frame;
}

std::unique_ptr<VelocityField> make_surface_velocity(const FluidFrame& a, const FluidFrame& b) {
  return std::make_unique<SurfaceVelocity>(a, b);
}

std::unique_ptr<VelocityField> make_grid_velocity(vol::RgbGrid a, double t_a, vol::RgbGrid b,
                                                  double t_b) {
  return std::make_unique<GridVelocity>(std::move(a), t_a, std::move(b), t_b);
}

} // namespace texsim::pipelines::fluid_lapped
