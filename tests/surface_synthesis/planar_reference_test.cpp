// Wei-Levoy on a flat grid must be Wei-Levoy 2000 on an image: a pyramid of regular grid meshes
// (given, not retiled; level k has spacing 2^k h, so d_k = sqrt(2 A_k) is the grid spacing and
// every current-level sample lands on a vertex), frames aligned with the grid, must pick for every
// vertex the same exemplar pixel as a plain 2D implementation written here: same order (the
// pipeline's classes), same template, the coarser level read at (x, y) / 2. The exemplar is
// random and large enough (32 x 32, 4 x 4 at the top) that no two of its neighbourhoods are equal:
// an exact tie in the exemplar would be broken by round-off in the mesh weights.
#include "core/rng.hpp"
#include "geom/aabb_tree.hpp"
#include "pipelines/surface_synthesis/exemplar_pyramid.hpp"
#include "pipelines/surface_synthesis/level_stencils.hpp"
#include "pipelines/surface_synthesis/level_synthesizer.hpp"
#include "pipelines/surface_synthesis/parent_faces.hpp"
#include "pipelines/surface_synthesis/pyramid_synthesis.hpp"
#include "pipelines/surface_synthesis/synthesis_order.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr double kSpacing = 0.25;

/// Grid vertex (i, j) = id j * side + i at (i h, -j h, 0): image x to the right, y down, seen from
/// +z with s = +x and t = +y. Quads split along (i, j)-(i+1, j+1), counter-clockwise from +z.
geom::TriangleMesh grid_mesh(int side, double h) {
  geom::TriangleMesh mesh;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i)
      mesh.positions.emplace_back(i * h, -j * h, 0.0);
  const auto id = [&](int i, int j) { return std::int32_t(j * side + i); };
  for (int j = 0; j + 1 < side; ++j)
    for (int i = 0; i + 1 < side; ++i) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
      mesh.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
    }
  return mesh;
}

/// The grid as a level on one rank: normals +z and spacing h (sqrt(2 h^2 / 2)).
RetiledLevel grid_level(const geom::TriangleMesh& grid) {
  const par::Comm self{MPI_COMM_SELF, 0, 1};
  return distribute_level(self, grid, {0, std::int64_t(grid.positions.size())});
}

img::RgbImage random_exemplar(int size) {
  const CounterRng rng(17, 3);
  img::RgbImage image(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c)
        image.at(x, y)[c] = float(rng.uniform(std::uint64_t(y * size + x), std::uint32_t(c)));
  return image;
}

struct Rgbd {
  double v[3] = {0, 0, 0};
};

Rgbd to_double(const img::Rgb& c) {
  return {{c.r, c.g, c.b}};
}

Rgbd image_mean(const img::RgbImage& image) {
  Rgbd mean;
  for (const auto& c : image.data())
    for (int ch = 0; ch < 3; ++ch)
      mean.v[ch] += c[ch];
  for (double& m : mean.v)
    m /= double(image.size());
  return mean;
}

/// Linear on the triangles of the pixel grid split along (x, y)-(x+1, y+1); `at(i, j)` reads a
/// pixel (periodic or not, the caller's business).
template <class At> Rgbd piecewise_linear(At at, double x, double y) {
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  Rgbd out;
  const auto add = [&](int dx, int dy, double w) {
    if (w == 0)
      return;
    const Rgbd c = at(x0 + dx, y0 + dy);
    for (int ch = 0; ch < 3; ++ch)
      out.v[ch] += w * c.v[ch];
  };
  if (fx >= fy) {
    add(0, 0, 1 - fx);
    add(1, 0, fx - fy);
    add(1, 1, fy);
  } else {
    add(0, 0, 1 - fy);
    add(0, 1, fy - fx);
    add(1, 1, fx);
  }
  return out;
}

/// The 2D synthesis: out[k] holds each level's colours, side x side pixels, vertex order.
class PlanarWeiLevoy {
public:
  PlanarWeiLevoy(const std::vector<img::RgbImage>& exemplar, std::vector<NeighbourhoodShape> shapes)
      : exemplar_(exemplar), shapes_(std::move(shapes)) {}

  /// The neighbourhood of output pixel (x, y) of level k in `pass`.
  std::vector<double> output_neighbourhood(const std::vector<std::vector<img::Rgb>>& out,
                                           const std::vector<int>& sides, int k, Pass pass, int x,
                                           int y) const {
    const auto layout = layout_of(k);
    std::vector<double> values;
    const auto push = [&](const Rgbd& c) { values.insert(values.end(), c.v, c.v + 3); };
    const int side = sides[std::size_t(k)];
    if (pass == Pass::refine)
      for (const auto& o : layout.current) {
        const int px = x + int(o.x()), py = y + int(o.y());
        const bool inside = px >= 0 && py >= 0 && px < side && py < side;
        push(inside ? to_double(out[std::size_t(k)][std::size_t(py * side + px)])
                    : image_mean(exemplar_[std::size_t(k)]));
      }
    if (!layout.coarser.empty()) {
      const int coarse_side = sides[std::size_t(k) + 1];
      const auto& coarse = out[std::size_t(k) + 1];
      for (const auto& o : layout.coarser) {
        const double cx = 0.5 * x + o.x(), cy = 0.5 * y + o.y();
        const bool inside = cx >= 0 && cy >= 0 && cx <= coarse_side - 1 && cy <= coarse_side - 1;
        push(inside ? piecewise_linear(
                          [&](int i, int j) {
                            return to_double(coarse[std::size_t(j * coarse_side + i)]);
                          },
                          cx, cy)
                    : image_mean(exemplar_[std::size_t(k) + 1]));
      }
    }
    return values;
  }

  /// Exhaustive search over the toroidal exemplar, ties to the lower pixel.
  int best_pixel(int k, Pass pass, const std::vector<double>& query) const {
    const auto& candidates = candidates_of(k, pass);
    double best = std::numeric_limits<double>::infinity();
    int best_pixel = -1;
    for (std::size_t p = 0; p < candidates.size(); ++p) {
      double d = 0;
      for (std::size_t i = 0; i < query.size(); ++i)
        d += (query[i] - candidates[p][i]) * (query[i] - candidates[p][i]);
      if (d < best) {
        best = d;
        best_pixel = int(p);
      }
    }
    return best_pixel;
  }

private:
  NeighbourhoodTemplate layout_of(int k) const {
    return NeighbourhoodTemplate::from_shape(shapes_[std::size_t(k)],
                                             std::size_t(k) + 1 < exemplar_.size());
  }
  /// Every exemplar pixel's neighbourhood at level k in `pass`, in pixel order (computed once).
  const std::vector<std::vector<double>>& candidates_of(int k, Pass pass) const {
    auto& cached = candidates_[{k, int(pass)}];
    if (!cached.empty())
      return cached;
    const auto layout = layout_of(k);
    const auto& image = exemplar_[std::size_t(k)];
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) {
        std::vector<double> candidate;
        const auto push = [&](const Rgbd& c) { candidate.insert(candidate.end(), c.v, c.v + 3); };
        if (pass == Pass::refine)
          for (const auto& o : layout.current)
            push(to_double(image.periodic(x + int(o.x()), y + int(o.y()))));
        for (const auto& o : layout.coarser)
          push(piecewise_linear(
              [&](int i, int j) { return to_double(exemplar_[std::size_t(k) + 1].periodic(i, j)); },
              0.5 * x + o.x(), 0.5 * y + o.y()));
        cached.push_back(std::move(candidate));
      }
    return cached;
  }

  const std::vector<img::RgbImage>& exemplar_;
  std::vector<NeighbourhoodShape> shapes_;
  mutable std::map<std::pair<int, int>, std::vector<std::vector<double>>> candidates_;
};

/// Grid levels of (finest_side - 1) / 2^k + 1 vertices per side, frames along the grid.
struct GridPyramid {
  std::vector<RetiledLevel> pyramid;
  std::vector<int> sides;
  std::vector<std::vector<geom::Vec3>> directions;
  std::vector<std::vector<ParentFace>> parents;

  GridPyramid(int levels, int finest_side) {
    std::vector<geom::TriangleMesh> grids;
    for (int k = 0; k < levels; ++k) {
      sides.push_back((finest_side - 1) / (1 << k) + 1);
      grids.push_back(grid_mesh(sides.back(), kSpacing * (1 << k)));
      pyramid.push_back(grid_level(grids.back()));
    }
    parents.resize(std::size_t(levels));
    for (int k = 0; k < levels; ++k) {
      directions.emplace_back(grids[std::size_t(k)].positions.size(), geom::Vec3(1, 0, 0));
      if (k + 1 < levels) {
        const geom::AabbTree tree(grids[std::size_t(k) + 1]);
        parents[std::size_t(k)] =
            find_parent_faces(grids[std::size_t(k)].positions, pyramid[std::size_t(k)].normals,
                              grids[std::size_t(k) + 1], tree);
      }
    }
  }
};

void expect_same_picks_as_planar(int levels, std::vector<NeighbourhoodShape> shapes) {
  const par::Comm self{MPI_COMM_SELF, 0, 1};
  const GridPyramid grid(levels, (1 << (levels - 1)) * 8 + 1);
  const auto& [pyramid, sides, directions, parents] = grid;
  const auto exemplar = exemplar_pyramid(random_exemplar(32), levels, ExemplarBorder::toroidal);
  PyramidSynthesisInput input{pyramid, directions, parents, exemplar};
  input.shapes = shapes;
  input.seed = 9;

  // The pipeline, recording the classes of each pass.
  std::vector<std::vector<std::int32_t>> pass2_classes(static_cast<std::size_t>(levels));
  for (int k = 0; k < levels; ++k) {
    const auto layout = NeighbourhoodTemplate::from_shape(shapes[std::size_t(k)], k + 1 < levels);
    const RetiledLevel& level = pyramid[std::size_t(k)];
    const auto stencils = build_level_stencils(
        self, level, level.positions, level.normals, directions[std::size_t(k)],
        k + 1 < levels ? &pyramid[std::size_t(k) + 1] : nullptr, parents[std::size_t(k)], layout, 0,
        level.vertex_count());
    if (k == 0) {
      EXPECT_GT(stencils.uncovered(), 0) << "the grid's border leaves samples uncovered";
    }
    const std::vector<std::int64_t> one_run{0, level.vertex_count()};
    pass2_classes[std::size_t(k)] =
        synthesis_order(self, stencils, one_run, input.seed, k, Pass::refine).owned_class;
  }
  auto colours = random_start(pyramid, exemplar, input.seed, 0);
  StageTimers timers;
  synthesize_pyramid(self, input, colours, std::nullopt, {}, timers);

  // The planar reference from the same random start.
  const PlanarWeiLevoy planar(exemplar, shapes);
  auto start = random_start(pyramid, exemplar, input.seed, 0);
  std::vector<std::vector<img::Rgb>> out;
  for (const auto& level : start)
    out.push_back(level.colours);
  std::int64_t compared = 0, different = 0;
  for (int k = levels - 1; k >= 0; --k) {
    const int side = sides[std::size_t(k)];
    const auto n = std::size_t(side * side);
    std::vector<std::int32_t> picks(n, -1);
    const auto pick = [&](std::size_t v, Pass pass) {
      const auto query =
          planar.output_neighbourhood(out, sides, k, pass, int(v) % side, int(v) / side);
      picks[v] = planar.best_pixel(k, pass, query);
      out[std::size_t(k)][v] = exemplar[std::size_t(k)].data()[std::size_t(picks[v])];
    };
    if (k + 1 < levels)
      for (std::size_t v = 0; v < n; ++v)
        pick(v, Pass::extrapolate);
    if (NeighbourhoodTemplate::from_shape(shapes[std::size_t(k)], k + 1 < levels)
            .samples(Pass::refine) > 0) {
      const auto& classes = pass2_classes[std::size_t(k)];
      const std::int32_t count = *std::max_element(classes.begin(), classes.end()) + 1;
      for (std::int32_t c = 0; c < count; ++c)
        for (std::size_t v = 0; v < n; ++v)
          if (classes[v] == c)
            pick(v, Pass::refine);
    }
    if (picks[0] < 0)
      continue; // the coarsest level keeps its random start
    for (std::size_t v = 0; v < n; ++v) {
      ++compared;
      different += picks[v] != colours[std::size_t(k)].pixels[v];
    }
  }
  EXPECT_GT(compared, 0);
  EXPECT_EQ(different, 0) << "of " << compared << " vertices";
}

TEST(PlanarReference, OneLevelPicksTheSamePixels) {
  expect_same_picks_as_planar(1, {{5, 5, 1}});
}

TEST(PlanarReference, FourLevelsPickTheSamePixels) {
  expect_same_picks_as_planar(4, {{7, 7, 2}, {5, 5, 2}, {3, 3, 2}, {1, 1, 1}});
}

// An exactly periodic smooth exemplar (one lattice cell, 32 x 32) on a 129 x 129 grid, 4 levels,
// Wei-Levoy's neighbourhoods: the finest level's neighbourhood error falls below a fifth of the
// random start's (measured 0.185).
TEST(PlanarReference, LatticeExemplarOnAGridIsReproducedClosely) {
  const par::Comm self{MPI_COMM_SELF, 0, 1};
  const GridPyramid grid(4, 129);
  ExemplarSettings settings;
  settings.procedural = ProceduralExemplar::lattice;
  settings.size = 32;
  settings.periods = 1;
  const auto exemplar = exemplar_pyramid(load_exemplar(settings, 2), 4, ExemplarBorder::toroidal);
  PyramidSynthesisInput input{grid.pyramid, grid.directions, grid.parents, exemplar};
  input.shapes = {{7, 7, 2}, {5, 5, 2}, {3, 3, 2}, {1, 1, 1}};
  auto colours = random_start(grid.pyramid, exemplar, input.seed, 0);
  StageTimers timers;
  const auto report = synthesize_pyramid(self, input, colours, std::nullopt, {}, timers);
  EXPECT_LT(report.neighbourhood_error, 0.2 * report.random_start_error)
      << report.neighbourhood_error << " vs " << report.random_start_error;
}

} // namespace
} // namespace texsim::pipelines::surface_synthesis
