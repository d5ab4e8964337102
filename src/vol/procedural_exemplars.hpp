#pragma once
/// Procedural solid-texture exemplars: n^3 colour grids, deterministic per seed and periodic
/// (tileable) along every axis, so toroidal neighbourhoods make sense on them. Every generator is a
/// function of the tile coordinates (i, j, k) / n, so a 2n^3 exemplar sampled at even voxels equals
/// the n^3 one with the same seed.
#include "img/rgb.hpp"
#include "vol/dense_grid.hpp"

#include <cstdint>

namespace texsim::vol {

/// Marble: a colour ramp of sin(2 pi (stripes (u + w) + turbulence * T(u, v, w))), with T Perlin
/// turbulence (marble_exemplar.cpp).
struct MarbleParams {
  int stripes = 3;         ///< vein periods across the tile (integer keeps it tileable)
  double turbulence = 1.2; ///< amplitude of the turbulence added to the stripe phase
  int noise_period = 4;    ///< lattice cells per tile of the coarsest noise octave
  int octaves = 4;
};
RgbGrid marble_exemplar(int n, std::uint64_t seed, const MarbleParams& params = {});

/// Wood: rings around the axis through the tile centre along z; the radius is the distance to the
/// nearest periodic copy of that axis, perturbed by fBm (wood_exemplar.cpp).
struct WoodParams {
  int rings = 5;            ///< rings per unit of radius (tile units)
  double ring_noise = 0.08; ///< fBm amplitude added to the radius, tile units
  int noise_period = 2;
  int octaves = 4;
};
RgbGrid wood_exemplar(int n, std::uint64_t seed, const WoodParams& params = {});

/// Spherical particles: non-overlapping spheres placed by periodic dart throwing (Poisson-disk
/// like) until the coverage target is reached or the attempts run out (particle_exemplar.cpp).
struct ParticleParams {
  double radius = 0.08;          ///< sphere radius, tile units
  double min_gap = 0.01;         ///< smallest distance between two spheres' surfaces, tile units
  double target_coverage = 0.25; ///< volume fraction to aim for
  int max_attempts = 20000;
  img::Rgb particle{0.85f, 0.7f, 0.3f};
  img::Rgb background{0.15f, 0.22f, 0.4f};
};
RgbGrid particle_exemplar(int n, std::uint64_t seed, const ParticleParams& params = {});

/// Bricks: a 3D running bond (rows along y, layers along z, every other row/layer shifted by half
/// a brick along x) with mortar joints; each brick gets its own tint plus fine noise
/// (brick_exemplar.cpp).
struct BrickParams {
  int bricks_x = 2;     ///< bricks per tile along x
  int rows_y = 4;       ///< brick rows per tile along y (even, so the bond tiles)
  int layers_z = 2;     ///< brick layers per tile along z (even, so the bond tiles)
  double mortar = 0.02; ///< joint width, tile units
  img::Rgb brick{0.6f, 0.25f, 0.15f};
  img::Rgb mortar_colour{0.75f, 0.73f, 0.68f};
};
RgbGrid brick_exemplar(int n, std::uint64_t seed, const BrickParams& params = {});

/// Sea water (the thesis' case 4): homogeneous fBm in blue-green tones with sparse bright
/// highlights where a second, finer fBm exceeds a threshold (noise_exemplar.cpp).
struct NoiseParams {
  int noise_period = 4; ///< lattice cells per tile of the coarsest octave
  int octaves = 4;
  int highlight_period = 8;         ///< lattice cells per tile of the highlight noise
  double highlight_threshold = 0.5; ///< highlight fBm level above which the water turns bright
  double highlight_softness = 0.12; ///< fBm range over which a highlight fades in
  img::Rgb deep{0.05f, 0.22f, 0.33f};
  img::Rgb shallow{0.18f, 0.52f, 0.55f};
  img::Rgb highlight{0.92f, 0.97f, 0.98f};
};
RgbGrid noise_exemplar(int n, std::uint64_t seed, const NoiseParams& params = {});

/// Thin black and white strokes (the thesis' case 6): the tile is cut into `layers` slabs along z;
/// inside a slab the pattern is constant along z and made of noise-warped parallel strokes in a
/// direction of its own, so it is continuous along x and y and broken between slabs
/// (stroke_exemplar.cpp).
struct StrokeParams {
  int layers = 8;      ///< slabs per tile along z
  int strokes = 6;     ///< stroke periods per tile across the stroke direction
  double width = 0.12; ///< fraction of a period covered by each of the black and white strokes
  double warp = 0.35;  ///< fBm amplitude added to the stroke phase, periods
  int noise_period = 3;
  img::Rgb background{0.5f, 0.5f, 0.5f};
};
RgbGrid stroke_exemplar(int n, std::uint64_t seed, const StrokeParams& params = {});

/// Parallel planar stripes: colour = ramp(0.5 + 0.5 cos(2 pi periods v)) of y only, constant along
/// x and z (stripe_exemplar.cpp). No randomness: a reference for anisometric rotation.
struct StripeParams {
  int periods = 4; ///< stripes per tile along y (integer keeps it tileable)
  img::Rgb dark{0.1f, 0.12f, 0.3f};
  img::Rgb light{0.95f, 0.85f, 0.5f};
};
RgbGrid stripe_exemplar(int n, const StripeParams& params = {});

/// An exactly periodic exemplar: one period^3 cell of smooth random blobs (colours blended with
/// Gaussian weights of the distance to a few random centres on the cell's torus) tiled n / period
/// times along each axis, so voxel (i, j, k) equals voxel (i + period, j, k) bit for bit
/// (lattice_exemplar.cpp). Unlike the generators above it is defined in voxels, not tile units:
/// n must be a multiple of period.
RgbGrid lattice_exemplar(int n, int period, std::uint64_t seed);

} // namespace texsim::vol
