// Cascades through the binary, as docs/turk_rd.md describes them: a second stage with
// `active: "z > 0"` leaves every cell below the equator exactly at the first stage's values; the
// initiators (`at` a point with a radius, and a `region`) hold the values they set; with
// `active_start: initial` the active cells restart from the model's uniform state (a = b = 4),
// with `carried` they continue the first stage's pattern. 800 cells on the unit sphere, 2 ranks.
#include "support/run_command.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPPolyDataReader.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

namespace texsim {
namespace {
namespace fs = std::filesystem;

struct Cell {
  double a = 0, b = 0;
  double z_sum = 0; ///< summed z of the cell's polygon corners
  int corners = 0;
  double z() const { return z_sum / corners; }
};

/// Every cell of a cells_step_<step>.pvtp frame by id: species and the mean z of its pieces.
std::map<std::int64_t, Cell> read_cells(const fs::path& out, int step) {
  char name[64];
  std::snprintf(name, sizeof name, "frames/cells_step_%09d.pvtp", step);
  vtkNew<vtkXMLPPolyDataReader> reader;
  reader->SetFileName((out / name).c_str());
  reader->Update();
  vtkPolyData* cells = reader->GetOutput();
  vtkDataArray* ids = cells->GetCellData()->GetArray("cell_id");
  vtkDataArray* a = cells->GetCellData()->GetArray("a");
  vtkDataArray* b = cells->GetCellData()->GetArray("b");
  std::map<std::int64_t, Cell> by_id;
  if (ids == nullptr || a == nullptr || b == nullptr)
    return by_id;
  vtkNew<vtkIdList> corners;
  for (vtkIdType piece = 0; piece < cells->GetNumberOfCells(); ++piece) {
    auto& cell = by_id[std::int64_t(ids->GetTuple1(piece))];
    cell.a = a->GetTuple1(piece);
    cell.b = b->GetTuple1(piece);
    cells->GetCellPoints(piece, corners);
    for (vtkIdType k = 0; k < corners->GetNumberOfIds(); ++k) {
      cell.z_sum += cells->GetPoint(corners->GetId(k))[2];
      ++cell.corners;
    }
  }
  return by_id;
}

/// A first stage of `first_steps` steps of dt 1, then `second_steps` of the second stage with the
/// given start rule and, if asked, two initiators. Frames at the end of each stage.
fs::path run_cascade(const std::string& name, const std::string& active_start, int first_steps,
                     int second_steps, bool initiators) {
  const fs::path dir = test::scratch_dir("turk_rd_cascade_" + name);
  const fs::path config = dir / "cascade.yaml";
  std::ofstream yaml(config);
  yaml << "pipeline: turk_rd\nseed: 5\noutput: {dir: " << (dir / "out").string()
       << ", every: " << first_steps << "}\nturk_rd:\n  mesh: {generator: icosphere, level: 3}\n"
       << "  cells: {count: 800, relaxation: {iterations: 10}}\n  stages:\n"
       << "    first:\n      model: {type: turing_spots, s: 0.05}\n      steps: " << first_steps
       << "\n    second:\n      model: {type: turing_spots, s: 0.2}\n      steps: " << second_steps
       << "\n      dt: 0.5\n      active: \"z > 0\"\n      active_start: " << active_start << "\n";
  if (initiators)
    yaml << "      initiators:\n        dot: {at: [0, 0, 1], radius: 0.25, set: {b: 7}}\n"
         << "        band: {region: \"z > 0.2 && x > 0.6\", set: {a: 9}}\n";
  yaml.close();
  const auto outcome =
      test::run_command(test::texsim_under_mpirun(2) + " " + config.string() + " --quiet");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  return dir / "out";
}

TEST(TurkRdCascade, FrozenCellsHoldTheirValuesAndInitiatorsTheirs) {
  const auto out = run_cascade("frozen", "initial", 60, 60, true);
  const auto first = read_cells(out, 60), second = read_cells(out, 120);
  ASSERT_EQ(first.size(), 800u);
  ASSERT_EQ(second.size(), 800u);
  int below = 0, changed_above = 0, above = 0, dot = 0, band = 0;
  for (const auto& [id, cell] : second) {
    const auto& before = first.at(id);
    // The corners' mean lies within a cell of the centre; skip the cells at the equator.
    if (cell.z() < -0.15) {
      ++below;
      EXPECT_EQ(cell.a, before.a) << "frozen cell " << id << " changed";
      EXPECT_EQ(cell.b, before.b) << "frozen cell " << id << " changed";
    }
    if (cell.b == 7.0)
      ++dot;
    if (cell.a == 9.0)
      ++band;
    if (cell.z() > 0.15 && cell.b != 7.0 && cell.a != 9.0) {
      ++above;
      changed_above += cell.a != before.a;
    }
  }
  EXPECT_GT(below, 300);
  EXPECT_GT(above, 200);
  EXPECT_EQ(changed_above, above) << "active cells that did not change";
  // The initiator at the pole covers the cells within 0.25 (area pi 0.25^2 of 4 pi: ~12 cells);
  // the band z > 0.2, x > 0.6 about 80.
  EXPECT_GE(dot, 5);
  EXPECT_LE(dot, 30);
  EXPECT_GE(band, 40);
  EXPECT_LE(band, 160);
}

TEST(TurkRdCascade, ActiveStartInitialRestartsAndCarriedContinues) {
  // The first stage forms spots (1,000 steps); after one step of the second, its active cells are
  // still near where they started.
  const auto restarted = read_cells(run_cascade("initial", "initial", 1000, 1, false), 1001);
  const auto carried_out = run_cascade("carried", "carried", 1000, 1, false);
  const auto carried = read_cells(carried_out, 1001), first = read_cells(carried_out, 1000);
  ASSERT_EQ(restarted.size(), 800u);
  ASSERT_EQ(carried.size(), 800u);
  // Mean |difference| of a over the active cells (away from the frozen equator).
  double restarted_to_uniform = 0, restarted_to_first = 0, carried_to_first = 0,
         first_to_uniform = 0;
  int active = 0;
  for (const auto& [id, cell] : restarted) {
    if (cell.z() < 0.15)
      continue;
    ++active;
    restarted_to_uniform += std::abs(cell.a - 4.0);
    restarted_to_first += std::abs(cell.a - first.at(id).a);
    carried_to_first += std::abs(carried.at(id).a - first.at(id).a);
    first_to_uniform += std::abs(first.at(id).a - 4.0);
  }
  ASSERT_GT(active, 200);
  EXPECT_GT(first_to_uniform / active, 0.5) << "the first stage formed no pattern to carry";
  EXPECT_LT(restarted_to_uniform, 0.25 * first_to_uniform) << "active cells did not restart";
  EXPECT_LT(carried_to_first, 0.5 * restarted_to_first)
      << "carried cells did not continue from the first stage's values";
}

} // namespace
} // namespace texsim
