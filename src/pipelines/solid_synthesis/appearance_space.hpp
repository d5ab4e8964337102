#pragma once
/// The exemplar in appearance space (Su 2008, section 3.1, after Lefebvre & Hoppe 2006): every
/// voxel of every Gaussian-stack level gets the window^3 x C neighbourhood of that level, sampled
/// with taps 2^s apart, projected onto the level's principal axes. Nearest neighbours in this space
/// are what similarity sets and voxel correction match.
#include "par/comm.hpp"
#include "vol/channel_grid.hpp"

#include <Eigen/Dense>

#include <span>
#include <vector>

namespace texsim::pipelines::solid_synthesis {

/// How neighbourhoods treat the exemplar's faces.
enum class ExemplarBorder {
  toroidal, ///< the exemplar tiles: neighbourhoods wrap around (the thesis' default)
  discard,  ///< the faces do not match: drop window / 2 voxels on each face after computing
};

struct AppearanceOptions {
  int dimensions = 8; ///< appearance-vector length after PCA (components past window^3 * C are 0)
  int window = 5;     ///< neighbourhood edge in taps (odd)
  ExemplarBorder border = ExemplarBorder::toroidal;
};

/// One stack level in appearance space.
struct AppearanceLevel {
  int spacing = 1;           ///< h = 2^s: exemplar voxels between neighbourhood samples
  int window = 5;            ///< neighbourhood edge in taps
  vol::ChannelGrid features; ///< `dimensions` floats per working-exemplar voxel (node-shared)
  Eigen::VectorXd mean;      ///< window^3*C mean neighbourhood vector, tap-major (z, y, x), channel
                             ///< fastest
  /// (window^3*C) x dimensions principal axes, columns by decreasing variance, each with its
  /// largest-magnitude component positive. Columns past the level's number of directions with
  /// variance above float rounding (e.g. all of them on the constant coarsest level, or those past
  /// window^3*C) are zero, so those feature components are 0.
  Eigen::MatrixXd basis;
  double retained_variance = 0; ///< fraction of the neighbourhood variance the basis keeps
};

struct AppearanceSpace {
  vol::ChannelGrid colours;            ///< working exemplar (after discarding borders), C channels
  std::vector<vol::ChannelGrid> stack; ///< Gaussian stack of `colours`, level s spacing 2^s
  std::vector<AppearanceLevel> levels; ///< same indexing as stack
  bool periodic = true;                ///< toroidal exemplar (exclusion windows and lookups wrap)
};

/// Builds the stack and the appearance vectors of every level. Toroidal: stack and neighbourhoods
/// wrap. Discard (the thesis' "discard the data of 2 voxels on each border"): stack and
/// neighbourhoods clamp on the whole exemplar, then every level is cropped by window / 2 voxels
/// per face, so the finest level's features of the kept voxels see only real data; PCA uses the
/// kept voxels only. Split over `comm`: the statistics and principal axes of stack level s on
/// rank s mod size, the projection by x rows over all ranks; every rank gets the whole space,
/// the same bits for any rank and thread count, with each level's features held once per node
/// (read-only, vol::ChannelGrid::node_shared). Collective.
/// Throws Error (on every rank) if the window is not odd and positive, dimensions < 1, or the
/// exemplar is smaller than the window along an axis.
AppearanceSpace build_appearance_space(const par::Comm& comm, const vol::ChannelGrid& exemplar,
                                       const AppearanceOptions& options);
/// The same in this process alone.
AppearanceSpace build_appearance_space(const vol::ChannelGrid& exemplar,
                                       const AppearanceOptions& options);

/// The appearance vector of the window^3 neighbourhood of voxel (i,j,k) of `colours` (periodic
/// lookups), projected with `level`'s PCA at spacing 1 — used to measure a synthesized volume in
/// the exemplar's appearance space. `colours` has the exemplar's channel count; `out` holds
/// level.basis.cols() floats.
void project_neighbourhood(const AppearanceLevel& level, const vol::ChannelGrid& colours, int i,
                           int j, int k, std::span<float> out);

} // namespace texsim::pipelines::solid_synthesis
