// Wei-Levoy synthesis on retiled surfaces: the colour classes are independent (no member's
// stencil reads another), the result has the same bytes on 1, 2 and 3 ranks as on one rank alone,
// and it is much closer to the exemplar's neighbourhoods than its random start: below half of it
// on a sphere, below a fifth with an exactly periodic lattice exemplar on a flat grid; with a
// stripe exemplar, relaxed orientation beats random orientation, and s along the parallels lays
// the stripes along them (the luminance varies along the meridians).
#include "geom/aabb_tree.hpp"
#include "geom/generators.hpp"
#include "pipelines/surface_synthesis/exemplar_pyramid.hpp"
#include "pipelines/surface_synthesis/level_stencils.hpp"
#include "pipelines/surface_synthesis/level_synthesizer.hpp"
#include "pipelines/surface_synthesis/orientation_relaxation.hpp"
#include "pipelines/surface_synthesis/parent_faces.hpp"
#include "pipelines/surface_synthesis/pyramid_synthesis.hpp"
#include "pipelines/surface_synthesis/run_star.hpp"
#include "pipelines/surface_synthesis/synthesis_order.hpp"
#include "whole_level.hpp"

#include <gtest/gtest.h>

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <span>
#include <type_traits>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// How the pyramid's texture directions s are chosen.
enum class Orientation {
  random,
  relaxed,  ///< 2-way relaxation, 30 sweeps a level
  parallels ///< the field (-y, x, 0) projected: s along the parallels about the z axis
};

/// A pyramid with everything the synthesis loop reads.
struct Prepared {
  std::vector<RetiledLevel> pyramid;
  std::vector<std::vector<geom::Vec3>> directions;
  std::vector<std::vector<ParentFace>> parents;

  Prepared(const par::Comm& comm, std::vector<RetiledLevel> levels, Orientation orientation)
      : pyramid(std::move(levels)) {
    constexpr int kSymmetry = 2;
    const int n = int(pyramid.size());
    parents.resize(std::size_t(n));
    directions.resize(std::size_t(n));
    for (int k = n - 1; k >= 0; --k) {
      const auto K = std::size_t(k);
      const std::int64_t first = pyramid[K].run_begin(comm.rank);
      const auto& normals = pyramid[K].normals; // this rank's run
      if (k + 1 < n)
        parents[K] = find_parent_faces(comm, pyramid[K], pyramid[K + 1]);
      const auto random = random_directions(normals, 5, k, first);
      directions[K] = random;
      if (orientation == Orientation::parallels) {
        std::vector<geom::Vec3> field;
        for (const auto& p : pyramid[K].positions)
          field.emplace_back(-p.y(), p.x(), 0.0);
        directions[K] = projected_directions(normals, field, nullptr);
      }
      if (orientation != Orientation::relaxed)
        continue;
      std::optional<CoarserOrientation> coarser;
      if (k + 1 < n) {
        coarser = coarser_orientation(comm, parents[K], pyramid[K + 1].rank_offsets,
                                      directions[K + 1], pyramid[K + 1].normals);
        directions[K] = inherited_directions(normals, *coarser, kSymmetry, random);
      }
      relax_directions(comm, pyramid[K].rank_offsets, run_rings(pyramid[K], comm.rank),
                       pyramid[K].normals, coarser ? &*coarser : nullptr, kSymmetry, 30,
                       directions[K]);
    }
  }

  PyramidSynthesisInput input(const std::vector<img::RgbImage>& exemplar) const {
    PyramidSynthesisInput in{pyramid, directions, parents, exemplar};
    // Wei-Levoy's {7x7,2}, {5x5,2}, {3x3,2}, {1x1,1}, finest first; fewer levels keep the coarsest.
    const std::vector<NeighbourhoodShape> shapes{{7, 7, 2}, {5, 5, 2}, {3, 3, 2}, {1, 1, 1}};
    in.shapes.assign(shapes.end() - std::ptrdiff_t(pyramid.size()), shapes.end());
    in.seed = 3;
    return in;
  }
};

std::vector<RetiledLevel> sphere_pyramid(const par::Comm& comm, std::int64_t vertices,
                                         int levels = 3) {
  MeshPyramidSettings settings;
  settings.finest_count = vertices;
  settings.levels = levels;
  settings.cells.relaxation.iterations = 15;
  return build_mesh_pyramid(comm, geom::icosphere(4), 11, settings);
}

/// The toroidal pyramid of a procedural exemplar (seed 2).
std::vector<img::RgbImage> procedural(ProceduralExemplar kind, int size, int periods, int levels) {
  ExemplarSettings settings;
  settings.procedural = kind;
  settings.size = size;
  settings.periods = periods;
  return exemplar_pyramid(load_exemplar(settings, 2), levels, ExemplarBorder::toroidal);
}

std::vector<img::RgbImage> lattice(int levels) {
  return procedural(ProceduralExemplar::lattice, 32, 1, levels);
}

/// A 64 x 64 tile of 8 cosine stripes varying along y: 8 pixels a period, 4 a level up, 2 and
/// then none on the two top levels (as in config/surface_synthesis/sphere_stripes_*.yaml).
std::vector<img::RgbImage> stripes(int levels) {
  return procedural(ProceduralExemplar::stripes, 64, 8, levels);
}

/// How much of the luminance's variation runs along the meridians (the directions of the z axis
/// in the tangent planes): sum (g . m)^2 / sum |g|^2 over the level's triangles, g the gradient
/// of the luminance's linear interpolation, m the unit meridian at the centroid, both weighted by
/// the triangle's area; triangles within about 17 degrees of a pole, where m turns fast, are left
/// out. 1 for colour a function of latitude alone (stripes along the parallels), about 1/2 for
/// no preferred direction.
double meridian_alignment(const geom::TriangleMesh& level, const LevelColours& colours) {
  const auto luminance = [&](std::int32_t v) {
    const img::Rgb& c = colours.colours[std::size_t(v)];
    return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
  };
  double along = 0, total = 0;
  for (const auto& t : level.triangles) {
    const geom::Vec3 &a = level.positions[std::size_t(t[0])],
                     &b = level.positions[std::size_t(t[1])],
                     &c = level.positions[std::size_t(t[2])];
    const geom::Vec3 e1 = b - a, e2 = c - a, n = e1.cross(e2);
    const geom::Vec3 gradient = (n.cross(e2) * (luminance(t[1]) - luminance(t[0])) +
                                 e1.cross(n) * (luminance(t[2]) - luminance(t[0]))) /
                                n.squaredNorm();
    const geom::Vec3 centre = ((a + b + c) / 3.0).normalized();
    const geom::Vec3 meridian = geom::Vec3(0, 0, 1) - centre * centre.z();
    if (meridian.norm() < 0.3)
      continue;
    const double area = 0.5 * n.norm();
    along += area * std::pow(gradient.dot(meridian.normalized()), 2);
    total += area * gradient.squaredNorm();
  }
  return total > 0 ? along / total : 0.0;
}

struct Run {
  std::vector<LevelColours> colours; ///< every vertex of every level, on every rank
  PyramidSynthesisReport report;
};

Run synthesize(const par::Comm& comm, const Prepared& prepared,
               const std::vector<img::RgbImage>& exemplar, SearchMethod method) {
  Run run;
  auto input = prepared.input(exemplar);
  input.method = method;
  run.colours = random_start(prepared.pyramid, exemplar, input.seed, comm.rank);
  StageTimers timers;
  run.report = synthesize_pyramid(comm, input, run.colours, std::nullopt, {}, timers);
  // The runs completed into whole levels, for the checks below.
  for (std::size_t k = 0; k < run.colours.size(); ++k) {
    const auto& offsets = prepared.pyramid[k].rank_offsets;
    auto& level = run.colours[k];
    const auto first = std::ptrdiff_t(offsets[std::size_t(comm.rank)]);
    const auto whole = [&](const auto& run_values) {
      std::remove_cvref_t<decltype(run_values)> all(std::size_t(offsets.back()));
      std::copy(run_values.begin(), run_values.end(), all.begin() + first);
      return all;
    };
    level.colours = whole(level.colours);
    level.pixels = whole(level.pixels);
    static_assert(sizeof(img::Rgb) == 3 * sizeof(float));
    par::allgather_runs(comm, offsets, level.colours.data(), 3, MPI_FLOAT);
    par::allgather_runs(comm, offsets, level.pixels.data(), 1, MPI_INT32_T);
  }
  return run;
}

/// Every vertex's class of `order` on every rank.
std::vector<std::int32_t> all_classes(const par::Comm& comm,
                                      std::span<const std::int64_t> rank_offsets,
                                      const SynthesisOrder& order) {
  std::vector<int> counts(std::size_t(comm.size)), offsets(std::size_t(comm.size));
  for (int r = 0; r < comm.size; ++r) {
    offsets[std::size_t(r)] = int(rank_offsets[std::size_t(r)]);
    counts[std::size_t(r)] = int(rank_offsets[std::size_t(r) + 1] - rank_offsets[std::size_t(r)]);
  }
  std::vector<std::int32_t> classes(std::size_t(rank_offsets.back()));
  MPI_Allgatherv(order.owned_class.data(), int(order.owned_class.size()), MPI_INT32_T,
                 classes.data(), counts.data(), offsets.data(), MPI_INT32_T, comm.raw);
  return classes;
}

const auto kLayout = NeighbourhoodTemplate::from_shape({7, 7, 2}, true);

/// A 2048-vertex sphere's pyramid with random directions, and the stencils of this rank's run of
/// its finest level (kLayout).
struct FinestRun {
  explicit FinestRun(const par::Comm& comm)
      : prepared(comm, sphere_pyramid(comm, 2048), Orientation::random), level(prepared.pyramid[0]),
        stencils(build_level_stencils(comm, level, level.positions, level.normals,
                                      prepared.directions[0], &prepared.pyramid[1],
                                      prepared.parents[0], kLayout,
                                      level.rank_offsets[std::size_t(comm.rank)],
                                      level.rank_offsets[std::size_t(comm.rank) + 1] -
                                          level.rank_offsets[std::size_t(comm.rank)])) {}
  Prepared prepared;
  const RetiledLevel& level;
  LevelStencils stencils;
};

// A rank holds the colours of its run, of the vertices its stencils read on other ranks and of
// the coarser vertices they read, nothing more: the halo is exactly the set the stencils read,
// and every renumbered sample names the vertex it named before.
TEST(Synthesis, HaloIsWhatTheStencilsRead) {
  const par::Comm comm = par::world();
  const FinestRun run(comm);
  const auto& [prepared, level, stencils] = run;
  const auto first = stencils.first, owned = stencils.owned;
  const LevelSynthesizer synthesizer(comm, stencils, level.rank_offsets,
                                     prepared.pyramid[1].rank_offsets, lattice(3), 0, kLayout,
                                     SearchMethod::exhaustive, ExemplarBorder::toroidal, 3);
  std::set<std::int64_t> read, coarser_read;
  for (const auto& sample : stencils.current)
    if (sample.covered())
      for (const auto v : sample.vertices)
        if (v < first || v >= first + owned)
          read.insert(v);
  for (const auto& sample : stencils.coarser)
    if (sample.covered())
      coarser_read.insert(sample.vertices.begin(), sample.vertices.end());
  const auto halo = synthesizer.halo();
  const auto coarser_reads = synthesizer.coarser_reads();
  EXPECT_EQ(std::vector<std::int64_t>(halo.begin(), halo.end()),
            std::vector<std::int64_t>(read.begin(), read.end()));
  EXPECT_EQ(std::vector<std::int64_t>(coarser_reads.begin(), coarser_reads.end()),
            std::vector<std::int64_t>(coarser_read.begin(), coarser_read.end()));
  if (comm.size > 1) {
    EXPECT_GT(halo.size(), 0u);
    EXPECT_LT(std::int64_t(halo.size()), level.vertex_count() - owned);
  }
  const auto& local = synthesizer.stencils();
  ASSERT_EQ(local.current.size(), stencils.current.size());
  ASSERT_EQ(local.coarser.size(), stencils.coarser.size());
  const auto level_id = [&](std::int32_t id) {
    return id < owned ? first + id : halo[std::size_t(id - owned)];
  };
  for (std::size_t i = 0; i < stencils.current.size(); ++i)
    if (stencils.current[i].covered()) {
      for (std::size_t k = 0; k < 3; ++k)
        ASSERT_EQ(level_id(local.current[i].vertices[k]), stencils.current[i].vertices[k]);
    }
  for (std::size_t i = 0; i < stencils.coarser.size(); ++i)
    if (stencils.coarser[i].covered()) {
      for (std::size_t k = 0; k < 3; ++k)
        ASSERT_EQ(coarser_reads[std::size_t(local.coarser[i].vertices[k])],
                  stencils.coarser[i].vertices[k]);
    }
}

TEST(Synthesis, NoClassMemberReadsAnother) {
  const par::Comm comm = par::world();
  const FinestRun run(comm);
  const auto& [prepared, level, stencils] = run;
  const auto first = stencils.first, owned = stencils.owned;
  const auto order = synthesis_order(comm, stencils, level.rank_offsets, 3, 0, Pass::refine);
  EXPECT_GT(order.classes, 1);
  const auto class_of = all_classes(comm, level.rank_offsets, order);
  std::int64_t reads = 0;
  for (std::int64_t local = 0; local < owned; ++local)
    for (const auto& sample : stencils.current_of(local))
      for (std::size_t k = 0; k < 3; ++k)
        if (sample.covered() && sample.weights[k] != 0 && sample.vertices[k] != first + local) {
          ++reads;
          EXPECT_NE(class_of[std::size_t(sample.vertices[k])],
                    class_of[std::size_t(first + local)]);
        }
  EXPECT_GT(reads, 0);
}

// The distributed colouring equals the sequential greedy colouring that visits the vertices in
// priority order, built here from the whole level's stencils.
TEST(Synthesis, ClassesAreTheSequentialGreedyColouring) {
  const par::Comm comm = par::world();
  const Prepared prepared(comm, sphere_pyramid(comm, 2048), Orientation::random);
  const auto& level = prepared.pyramid[0];
  const auto n = level.vertex_count();
  // The whole level's positions, normals, directions and parent faces, for the whole level's
  // stencils below.
  const auto positions = whole_runs(comm, level, level.positions);
  const auto normals = whole_runs(comm, level, level.normals);
  const auto directions = whole_runs(comm, level, prepared.directions[0]);
  const auto coarser_mesh = whole_level_mesh(comm, prepared.pyramid[1]);
  const auto parents =
      find_parent_faces(positions, normals, coarser_mesh, geom::AabbTree(coarser_mesh));
  const auto stencils_of = [&](std::int64_t first, std::int64_t owned) {
    const auto run = [&](const auto& all) {
      return std::span(all).subspan(std::size_t(first), std::size_t(owned));
    };
    return build_level_stencils(comm, level, run(positions), run(normals), run(directions),
                                &prepared.pyramid[1], run(parents), kLayout, first, owned);
  };
  const auto first = level.rank_offsets[std::size_t(comm.rank)];
  const auto owned = level.rank_offsets[std::size_t(comm.rank) + 1] - first;
  const auto run_stencils = stencils_of(first, owned);
  const auto order = synthesis_order(comm, run_stencils, level.rank_offsets, 3, 0, Pass::refine);
  const auto classes = all_classes(comm, level.rank_offsets, order);

  const auto whole = stencils_of(0, n); // every rank the whole level (collective)
  // The run's stencils, flattened on parts fetched from the other ranks, are the whole level's.
  for (std::int64_t i = 0; i < owned; ++i)
    for (const auto& [found, expected] :
         {std::pair(run_stencils.current_of(i), whole.current_of(first + i)),
          std::pair(run_stencils.coarser_of(i), whole.coarser_of(first + i))}) {
      ASSERT_EQ(found.size(), expected.size());
      EXPECT_EQ(std::memcmp(found.data(), expected.data(), found.size() * sizeof(SampleWeights)), 0)
          << "vertex " << first + i;
    }
  std::vector<std::vector<std::int64_t>> neighbours(static_cast<std::size_t>(n));
  for (std::int64_t u = 0; u < n; ++u)
    for (const auto& sample : whole.current_of(u))
      for (std::size_t k = 0; k < 3; ++k)
        if (sample.covered() && sample.weights[k] != 0 && sample.vertices[k] != u) {
          neighbours[std::size_t(u)].push_back(sample.vertices[k]);
          neighbours[std::size_t(sample.vertices[k])].push_back(u);
        }
  std::vector<std::pair<std::uint64_t, std::int64_t>> visits;
  for (std::int64_t v = 0; v < n; ++v)
    visits.push_back({synthesis_priority(3, 0, Pass::refine, v), v});
  std::sort(visits.begin(), visits.end());
  std::vector<std::int32_t> expected(std::size_t(n), -1);
  for (const auto& [key, v] : visits) {
    std::vector<bool> taken(neighbours[std::size_t(v)].size() + 1, false);
    for (const auto u : neighbours[std::size_t(v)])
      if (expected[std::size_t(u)] >= 0 && std::size_t(expected[std::size_t(u)]) < taken.size())
        taken[std::size_t(expected[std::size_t(u)])] = true;
    expected[std::size_t(v)] =
        std::int32_t(std::find(taken.begin(), taken.end(), false) - taken.begin());
  }
  EXPECT_EQ(classes, expected);
  EXPECT_EQ(order.classes, *std::max_element(expected.begin(), expected.end()) + 1);
}

TEST(Synthesis, SameBytesOnAnyRankCountAsOnOne) {
  const par::Comm world = par::world();
  const par::Comm self{MPI_COMM_SELF, 0, 1};
  const auto exemplar = lattice(3);
  const Prepared distributed(world, sphere_pyramid(world, 1024), Orientation::relaxed);
  const Prepared alone(self, sphere_pyramid(self, 1024), Orientation::relaxed);
  for (const auto method : {SearchMethod::exhaustive, SearchMethod::tsvq}) {
    const auto a = synthesize(world, distributed, exemplar, method);
    const auto b = synthesize(self, alone, exemplar, method);
    for (std::size_t k = 0; k < a.colours.size(); ++k) {
      ASSERT_EQ(a.colours[k].pixels, b.colours[k].pixels) << "level " << k;
      EXPECT_EQ(std::memcmp(a.colours[k].colours.data(), b.colours[k].colours.data(),
                            a.colours[k].colours.size() * sizeof(img::Rgb)),
                0);
    }
  }
}

TEST(Synthesis, SphereHalvesTheRandomStartsError) {
  const par::Comm comm = par::world();
  const Prepared prepared(comm, sphere_pyramid(comm, 4096), Orientation::random);
  const auto run = synthesize(comm, prepared, lattice(3), SearchMethod::pruned);
  EXPECT_LT(run.report.neighbourhood_error, 0.5 * run.report.random_start_error)
      << run.report.neighbourhood_error << " vs " << run.report.random_start_error;
}

TEST(Synthesis, StripesFollowTheirOrientation) {
  const par::Comm comm = par::world();
  const auto exemplar = stripes(4);
  auto levels = sphere_pyramid(comm, 8192, 4);
  const Prepared random(comm, levels, Orientation::random);
  const Prepared relaxed(comm, levels, Orientation::relaxed);
  const Prepared parallels(comm, std::move(levels), Orientation::parallels);
  const auto at_random = synthesize(comm, random, exemplar, SearchMethod::pruned);
  const auto relaxed_run = synthesize(comm, relaxed, exemplar, SearchMethod::pruned);
  const auto along_field = synthesize(comm, parallels, exemplar, SearchMethod::pruned);

  EXPECT_LT(relaxed_run.report.neighbourhood_error, at_random.report.neighbourhood_error);

  const auto finest = whole_level_mesh(comm, random.pyramid.front());
  const double aligned = meridian_alignment(finest, along_field.colours.front());
  const double unaligned = meridian_alignment(finest, at_random.colours.front());
  // The exemplar varies along its y axis, t = n x s: with s along the parallels, along the
  // meridians. Random s leaves no preferred direction.
  EXPECT_GT(aligned, 0.7) << "random orientation: " << unaligned;
  EXPECT_LT(unaligned, 0.6) << "along the field: " << aligned;
  EXPECT_GT(along_field.report.levels.back().distinct_colours, 1) << "one colour at level 0";
}

} // namespace
} // namespace texsim::pipelines::surface_synthesis
