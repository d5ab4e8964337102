#include "pipelines/fluid_lapped/fluid_frames.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_remesh.hpp"
#include "geom/mesh_validation.hpp"
#include "io/pvd_series.hpp"

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

/// A surface with the velocity at its vertices, as stored in the file.
FluidFrame read_stored(const std::filesystem::path& path, const std::string& velocity_array) {
  FluidFrame frame;
  if (velocity_array.empty()) {
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

} // namespace

FrameSource::FrameSource(FrameSourceSettings settings) : settings_(std::move(settings)) {
  const std::filesystem::path spec = settings_.frames;
  if (spec.extension() == ".pvd") {
    for (const auto& entry : io::PvdSeries::read_entries(spec)) {
      files_.push_back(spec.parent_path() / entry.file);
      times_.push_back(entry.time);
    }
  } else if (settings_.frames.find('%') != std::string::npos) {
    int first = std::filesystem::exists(pattern_name(settings_.frames, 0)) ? 0 : 1;
    for (int k = first; std::filesystem::exists(pattern_name(settings_.frames, k)); ++k) {
      files_.push_back(pattern_name(settings_.frames, k));
      times_.push_back(k * settings_.frame_interval);
    }
  } else {
    TEXSIM_INPUT_ERROR(kKey << ": '" << settings_.frames
                            << "' is neither a .pvd nor a name pattern with a printf integer "
                               "(frames/surface_%04d.vtp)");
  }
  if (files_.empty())
    TEXSIM_INPUT_ERROR(kKey << ": no frame found for '" << settings_.frames << "'");
  for (std::size_t k = 0; k < files_.size(); ++k) {
    if (!std::filesystem::is_regular_file(files_[k]))
      TEXSIM_INPUT_ERROR(kKey << ": frame " << k << " of " << settings_.frames << ", "
                              << files_[k].string() << ", is missing");
    if (k > 0 && !(times_[k] > times_[k - 1]))
      TEXSIM_INPUT_ERROR(kKey << ": the times of " << settings_.frames << " must increase; frame "
                              << k << " has " << times_[k] << " after " << times_[k - 1]);
  }
  edge_length_ = settings_.edge_length > 0
                     ? settings_.edge_length
                     : geom::mean_edge_length(read_stored(files_.front(), "").mesh);
}

FluidFrame FrameSource::read(int k) const {
  const auto& path = files_[std::size_t(k)];
  auto stored = read_stored(path, settings_.velocity_array);
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

} // namespace texsim::pipelines::fluid_lapped
