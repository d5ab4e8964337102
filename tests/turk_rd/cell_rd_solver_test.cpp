// Turk's explicit reaction-diffusion on cells: diffusion alone conserves sum A_i c_i and relaxes to
// the area-weighted mean; the spot system gives the same bits on any number of ranks as on one;
// frozen cells keep their values; a dt above the stability limit runs as stable substeps.
#include "core/config.hpp"
#include "geom/generators.hpp"
#include "pipelines/turk_rd/cell_rd_solver.hpp"
#include "support/gather_by_id.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace texsim::pipelines::turk_rd {
namespace {

std::unique_ptr<rd::ReactionModel> model_from(const std::string& yaml) {
  auto config = ConfigDocument::parse(yaml, "test");
  return rd::make_reaction_model(config.root(), 11);
}

geom::SurfaceCells make_cells(const par::Comm& comm, const geom::TriangleMesh& mesh,
                              std::int64_t count) {
  geom::SurfaceCellsSettings settings;
  settings.count = count;
  settings.relaxation.iterations = 15;
  return geom::SurfaceCells(comm, geom::DistributedTriangles::from_replicated(comm, mesh), 2,
                            settings);
}

TEST(CellRdSolver, DiffusionConservesAndRelaxesToTheMean) {
  const par::Comm comm = par::world();
  const auto mesh = geom::icosphere(3);
  const auto cells = make_cells(comm, mesh, 600);
  // A diffusing species whose reaction is zero, starting from a function of position; diffusion
  // 1.5 times as fast on one half of the sphere (the couplings must stay symmetric for
  // conservation).
  const auto model = model_from("type: expression\nspecies:\n  u: {diffusion: 0.1, initial: "
                                "\"x + 0.5 * y * y\"}\n");
  std::vector<double> scale;
  for (const auto& p : cells.points())
    scale.push_back(p.position.x() > 0 ? 1.5 : 1.0);
  CellRdSolver solver(comm, cells, *model, scale, 1.0);
  ASSERT_LE(solver.dt(), solver.max_stable_dt());
  const double initial = solver.integral(0);
  const double mean = initial / cells.surface_area();
  const auto spread = [&] {
    const auto values = solver.owned_values(0);
    double local = 0;
    for (const double v : values)
      local = std::max(local, std::abs(v - mean));
    double global = 0;
    MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, comm.raw);
    return global;
  };
  const double spread_before = spread();
  for (int n = 0; n < 4000; ++n)
    solver.step(n);
  EXPECT_NEAR(solver.integral(0), initial, 1e-12 * std::abs(initial) + 1e-13);
  EXPECT_GT(spread_before, 0.5);
  EXPECT_LT(spread(), 1e-3 * spread_before) << "did not relax to the mean " << mean;
}

TEST(CellRdSolver, SpotSystemIsBitIdenticalOnAnyRankCount) {
  const auto mesh = geom::icosphere(3);
  const auto model = model_from("type: turing_spots\ns: 0.05\n");
  const auto run = [&](const par::Comm& comm) {
    const auto cells = make_cells(comm, mesh, 1500);
    std::vector<double> scale(std::size_t(cells.owned_count()), 1.0);
    CellRdSolver solver(comm, cells, *model, scale, 1.0);
    // Freeze a few cells at a raised value: initiators must behave the same everywhere.
    std::vector<char> frozen(std::size_t(cells.owned_count()), 0);
    auto a = solver.owned_values(0);
    for (std::int32_t i = 0; i < cells.owned_count(); ++i)
      if (cells.ids()[i] % 97 == 0) {
        frozen[i] = 1;
        a[i] = 5.0;
      }
    solver.set_owned_values(0, a);
    solver.set_frozen(frozen);
    for (int n = 0; n < 300; ++n)
      solver.step(n);
    std::vector<double> both;
    for (std::int32_t i = 0; i < cells.owned_count(); ++i)
      for (std::size_t s = 0; s < 2; ++s)
        both.push_back(solver.owned_values(s)[i]);
    return test::gather_by_id(comm, cells.ids(), both, 2);
  };
  const auto distributed = run(par::world());
  const auto serial = run(test::self_comm());
  ASSERT_EQ(distributed.size(), serial.size());
  EXPECT_EQ(std::memcmp(distributed.data(), serial.data(), serial.size() * sizeof(double)), 0);
  for (std::size_t id = 0; id < serial.size() / 2; id += 97)
    EXPECT_EQ(serial[2 * id], 5.0) << "frozen cell " << id << " changed";
  const auto [lo, hi] = std::minmax_element(serial.begin(), serial.end());
  EXPECT_LT(*lo, 3.9) << "no pattern started";
  EXPECT_GT(*hi, 4.1);
}

TEST(CellRdSolver, DtAboveTheStabilityLimitRunsAsStableSubsteps) {
  const par::Comm comm = par::world();
  const auto cells = make_cells(comm, geom::icosphere(3), 600);
  const std::vector<double> scale(std::size_t(cells.owned_count()), 1.0);
  const auto spots = model_from("type: turing_spots\ns: 0.05\n");
  const double limit = CellRdSolver(comm, cells, *spots, scale, 1.0).max_stable_dt();

  // 2.5 limits at safety 0.9: ceil(2.5 / 0.9) = 3 substeps, the same bits as three steps of a
  // third of it.
  CellRdSolver split(comm, cells, *spots, scale, 2.5 * limit);
  EXPECT_EQ(split.substeps(), 3);
  EXPECT_EQ(split.substep_dt(), 2.5 * limit / 3.0);
  CellRdSolver small(comm, cells, *spots, scale, 2.5 * limit / 3.0);
  EXPECT_EQ(small.substeps(), 1);
  for (int n = 0; n < 20; ++n)
    split.step(n * split.dt());
  for (int n = 0; n < 60; ++n)
    small.step(n * small.dt());
  for (std::size_t s = 0; s < 2; ++s) {
    const auto a = split.owned_values(s), b = small.owned_values(s);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << "species " << s;
  }

  // Pure diffusion 40 limits at a time stays within the initial range (each substep is a convex
  // combination) and conserves the integral.
  const auto heat = model_from("type: expression\nspecies:\n  u: {diffusion: 0.25, initial: "
                               "\"x\"}\n");
  const double heat_limit = CellRdSolver(comm, cells, *heat, scale, 1.0).max_stable_dt();
  CellRdSolver coarse(comm, cells, *heat, scale, 40.0 * heat_limit);
  EXPECT_EQ(coarse.substeps(), std::int64_t(std::ceil(40.0 / 0.9)));
  const double initial = coarse.integral(0);
  for (int n = 0; n < 10; ++n)
    coarse.step(n * coarse.dt());
  EXPECT_NEAR(coarse.integral(0), initial, 1e-12);
  for (const double v : coarse.owned_values(0))
    EXPECT_LE(std::abs(v), 1.0 + 1e-12);
}

/// Turing's spot system seen only through the ReactionModel interface, so the solver cannot fuse
/// it into its stencil loop and takes the general path.
class OpaqueModel final : public rd::ReactionModel {
public:
  explicit OpaqueModel(const rd::ReactionModel& inner) : inner_(inner) {}
  std::vector<std::string> species() const override { return inner_.species(); }
  std::vector<std::vector<double>> initial_state(const rd::VertexData& v) const override {
    return inner_.initial_state(v);
  }
  void coefficients(double t, const std::vector<std::span<const double>>& state,
                    const rd::VertexData& vertices,
                    std::vector<rd::SpeciesCoefficients>& out) const override {
    inner_.coefficients(t, state, vertices, out);
  }
  double lower_bound(std::size_t s) const override { return inner_.lower_bound(s); }

private:
  const rd::ReactionModel& inner_;
};

TEST(CellRdSolver, FusedSpotKernelEqualsTheGeneralPath) {
  const par::Comm comm = par::world();
  const auto cells = make_cells(comm, geom::icosphere(3), 1200);
  const auto spots = model_from("type: turing_spots\ns: 0.05\n");
  const OpaqueModel opaque(*spots);
  const std::vector<double> scale(std::size_t(cells.owned_count()), 1.0);
  CellRdSolver fused(comm, cells, *spots, scale, 1.0);
  CellRdSolver general(comm, cells, opaque, scale, 1.0);
  for (int n = 0; n < 200; ++n) {
    fused.step(n);
    general.step(n);
  }
  for (std::size_t s = 0; s < 2; ++s) {
    const auto a = fused.owned_values(s), b = general.owned_values(s);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << "species " << s;
  }
}

/// A user system of `count` species that diffuse at their own rates, decay and feed each other
/// (bounded, so 100 steps stay finite), from fields of position.
std::unique_ptr<rd::ReactionModel> species_system(int count) {
  std::string yaml = "{type: expression, species: {";
  for (int s = 0; s < count; ++s)
    yaml += (s ? ", c" : "c") + std::to_string(s) +
            ": {diffusion: " + std::to_string(0.02 * (s + 1)) + ", initial: \"" +
            std::to_string(s + 1) + " + x * y + z * " + std::to_string(s) +
            "\", linear: \"-0.01\", source: \"0.005 * c" + std::to_string((s + 1) % 2) + "\"}";
  return model_from(yaml + "}}");
}

// The lane kernels (2 and 5 species: cells grouped by degree, sums side by side) add each cell's
// neighbours in the same order as the row-by-row path that serves other species counts, so a
// system and the same system with one more species give the same bits for the shared species.
TEST(CellRdSolver, LaneKernelsEqualTheRowByRowPath) {
  const par::Comm comm = par::world();
  const auto cells = make_cells(comm, geom::icosphere(3), 1500);
  std::vector<double> scale;
  for (const auto& p : cells.points())
    scale.push_back(1.0 + 0.5 * p.position.z() * p.position.z());
  for (const int lane_species : {2, 5}) {
    SCOPED_TRACE(lane_species);
    const auto lanes = species_system(lane_species);
    const auto rows = species_system(lane_species + 1);
    CellRdSolver lane_solver(comm, cells, *lanes, scale, 1.0);
    CellRdSolver row_solver(comm, cells, *rows, scale, 1.0);
    for (int n = 0; n < 100; ++n) {
      lane_solver.step(n);
      row_solver.step(n);
    }
    for (std::size_t s = 0; s < std::size_t(lane_species); ++s) {
      const auto a = lane_solver.owned_values(s), b = row_solver.owned_values(s);
      ASSERT_TRUE(std::all_of(a.begin(), a.end(), [](double v) { return std::isfinite(v); }));
      EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << "species " << s;
    }
  }
}

} // namespace
} // namespace texsim::pipelines::turk_rd
