#pragma once
/// The fluid's animated surface as simulators write it: a ParaView .pvd series or a numbered name
/// pattern of surfaces (.vtp .vtu .vtk .ply .obj .off) or OpenVDB level sets (.vdb, meshed at
/// their zero crossing), any topology per frame, with the velocity
/// as a 3-component point array (OpenFOAM's U after foamToVTK and a contour) or as a series of
/// .vti velocity grids (U resampled on a grid). Each frame is
/// repaired and isotropically remeshed, because the patches need even triangles (paper, 7).
#include "geom/aabb_tree.hpp"
#include "geom/triangle_mesh.hpp"
#include "pipelines/fluid_lapped/velocity_field.hpp"
#include "vol/dense_grid.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace texsim::pipelines::fluid_lapped {

/// One frame: its time, its surface and, when the input carries one, the velocity at the
/// surface's vertices.
struct FluidFrame {
  double time = 0;
  geom::TriangleMesh mesh;
  std::vector<geom::Vec3> vertex_velocity; ///< empty for analytic flows
};

/// fluid_lapped.frames for simulator files.
struct FrameSourceSettings {
  /// surfaces: a .pvd, or a pattern with one printf integer (`frames/surface_%04d.vtp`) counted
  /// from 0 (or 1 when frame 0 is missing) until a file is missing
  std::string frames;
  double frame_interval = 1.0; ///< interval: time between pattern frames
  /// velocity_array: 3-component point array of the surfaces (empty when velocity_grids is used)
  std::string velocity_array = "U";
  /// velocity_grids: a .pvd (or pattern) of .vti or .vdb vector grids holding the 3-component
  /// array or Vec3s grid `grid_array`, one per frame at the frames' times; empty: the point array
  std::string velocity_grids;
  std::string grid_array;                 ///< grid_array; empty: U in .vti, vel in .vdb
  std::string level_set_grid = "surface"; ///< level_set_grid: FloatGrid of .vdb frames
  /// edge_length: target of the isotropic remeshing; 0 = the mean edge of frame 0 as stored
  double edge_length = 0;
};

class FrameSource {
public:
  /// Lists the frames; InputError naming `fluid_lapped.frames.surfaces` or the file when there
  /// is none, a listed file is missing, or times do not increase.
  explicit FrameSource(FrameSourceSettings settings);

  int frame_count() const { return int(files_.size()); }
  double time(int k) const { return times_[std::size_t(k)]; }
  const std::filesystem::path& file(int k) const { return files_[std::size_t(k)]; }
  double edge_length() const { return edge_length_; }

  /// Velocity grid k (world space, origin and spacing of the .vti or the .vdb's transform); only
  /// with velocity_grids.
  vol::RgbGrid velocity_grid(int k) const;
  bool has_velocity_grids() const { return !grid_files_.empty(); }

  /// Frame k read, repaired (non-manifold parts split, oriented, degenerate and duplicate
  /// triangles dropped, tiny components kept: droplets are fluid too) and remeshed to
  /// edge_length(); the velocity moved to the new vertices from the closest point of the file's
  /// surface (barycentric). Serial; any rank may read any frame.
  FluidFrame read(int k) const;

private:
  FrameSourceSettings settings_;
  std::vector<std::filesystem::path> files_;
  std::vector<double> times_;
  std::vector<std::filesystem::path> grid_files_;
  double edge_length_ = 0;
};

/// The velocity from frame a to frame b: each frame's vertex velocity at the closest point of its
/// surface (barycentric), then (1 - s) v_a + s v_b with s = (t - t_a) / (t_b - t_a) clamped to
/// [0, 1]. Keeps copies of both frames.
std::unique_ptr<VelocityField> make_surface_velocity(const FluidFrame& a, const FluidFrame& b);

/// The velocity from grid a (time t_a) to grid b (time t_b): each grid trilinear in world space,
/// clamped at its border, then linear in time as make_surface_velocity().
std::unique_ptr<VelocityField> make_grid_velocity(vol::RgbGrid a, double t_a, vol::RgbGrid b,
                                                  double t_b);

} // namespace texsim::pipelines::fluid_lapped
