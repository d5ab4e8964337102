// Parallel VTK output: pieces written at n ranks read back through VTK's own parallel readers
// (as ParaView does) as one surface with every point, triangle and field value that was written,
// integer fields with their integer types; no temporary file is left behind.
#include "core/error.hpp"
#include "io/parallel_surface_writer.hpp"
#include "io/vtk_surface_writer.hpp"
#include "par/comm.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPPolyDataReader.h>
#include <vtkXMLPUnstructuredGridReader.h>

#include <cmath>
#include <fstream>
#include <map>

namespace texsim::io {
namespace {

/// A height-field grid of n x n quads, two triangles each, with point and cell fields that are
/// functions of the geometry, so each value read back can be checked against its position.
struct GridSurface {
  static constexpr int n = 12;
  static double height(double x, double y) { return std::sin(x) * std::cos(2 * y); }
  static int point_id(int i, int j) { return i * (n + 1) + j; }
  static int triangle_count() { return 2 * n * n; }
  static std::array<int, 3> triangle(int t) {
    const int quad = t / 2, i = quad / n, j = quad % n;
    if (t % 2 == 0)
      return {point_id(i, j), point_id(i + 1, j), point_id(i + 1, j + 1)};
    return {point_id(i, j), point_id(i + 1, j + 1), point_id(i, j + 1)};
  }
  static std::array<double, 3> position(int p) {
    const double x = 0.1 * (p / (n + 1)), y = 0.1 * (p % (n + 1));
    return {x, y, height(x, y)};
  }
};

/// The triangles [first, last) of the grid as a piece with its own local point numbering.
struct OwnedPiece {
  std::vector<double> xyz, height, velocity;
  std::vector<std::int64_t> triangles, point_id, triangle_id;
  std::vector<std::int32_t> rank;

  OwnedPiece(int first, int last) {
    std::map<int, std::int64_t> local;
    for (int t = first; t < last; ++t) {
      for (const int p : GridSurface::triangle(t)) {
        const auto [it, inserted] = local.emplace(p, static_cast<std::int64_t>(local.size()));
        if (inserted) {
          const auto pos = GridSurface::position(p);
          xyz.insert(xyz.end(), pos.begin(), pos.end());
          height.push_back(pos[2]);
          velocity.insert(velocity.end(), {pos[1], -pos[0], 2 * pos[2]});
          point_id.push_back(p);
        }
        triangles.push_back(it->second);
      }
      triangle_id.push_back(t);
      rank.push_back(t % 7);
    }
  }

  SurfacePiece piece() const {
    return {xyz,
            triangles,
            {{"height", 1, height}, {"velocity", 3, velocity}, {"point_id", 1, point_id}},
            {{"triangle_id", 1, triangle_id}, {"rank", 1, rank}}};
  }
};

/// Rank r's triangles; at 3 ranks rank 1 has none, to exercise empty pieces.
std::pair<int, int> triangle_range(const par::Comm& comm) {
  const int total = GridSurface::triangle_count();
  if (comm.size == 3) {
    const int bounds[4] = {0, total / 3, total / 3, total};
    return {bounds[comm.rank], bounds[comm.rank + 1]};
  }
  return {total * comm.rank / comm.size, total * (comm.rank + 1) / comm.size};
}

vtkSmartPointer<vtkPointSet> read_back(const std::filesystem::path& path, SurfaceFormat format) {
  if (format == SurfaceFormat::vtu) {
    auto reader = vtkSmartPointer<vtkXMLPUnstructuredGridReader>::New();
    reader->SetFileName(path.c_str());
    reader->Update();
    return vtkSmartPointer<vtkPointSet>(reader->GetOutput());
  }
  auto reader = vtkSmartPointer<vtkXMLPPolyDataReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  return vtkSmartPointer<vtkPointSet>(reader->GetOutput());
}

void expect_whole_surface(vtkPointSet& surface) {
  ASSERT_EQ(surface.GetNumberOfCells(), GridSurface::triangle_count());
  vtkDataArray* height = surface.GetPointData()->GetArray("height");
  vtkDataArray* velocity = surface.GetPointData()->GetArray("velocity");
  vtkDataArray* point_id = surface.GetPointData()->GetArray("point_id");
  vtkDataArray* id = surface.GetCellData()->GetArray("triangle_id");
  vtkDataArray* rank = surface.GetCellData()->GetArray("rank");
  ASSERT_TRUE(height && velocity && point_id && id && rank);
  ASSERT_EQ(velocity->GetNumberOfComponents(), 3);
  // Real fields stay Float64; integer fields keep their integer width.
  EXPECT_EQ(height->GetDataType(), VTK_DOUBLE);
  EXPECT_EQ(point_id->GetDataType(), VTK_TYPE_INT64);
  EXPECT_EQ(id->GetDataType(), VTK_TYPE_INT64);
  EXPECT_EQ(rank->GetDataType(), VTK_TYPE_INT32);
  // Every point's fields are exactly the functions of its position that were written.
  for (vtkIdType p = 0; p < surface.GetNumberOfPoints(); ++p) {
    double pos[3];
    surface.GetPoint(p, pos);
    EXPECT_EQ(height->GetTuple1(p), GridSurface::height(pos[0], pos[1]));
    EXPECT_EQ(pos[2], GridSurface::height(pos[0], pos[1]));
    EXPECT_EQ(velocity->GetComponent(p, 0), pos[1]);
    EXPECT_EQ(velocity->GetComponent(p, 2), 2 * pos[2]);
    const auto written = GridSurface::position(static_cast<int>(point_id->GetTuple1(p)));
    EXPECT_EQ(pos[0], written[0]);
    EXPECT_EQ(pos[1], written[1]);
  }
  // Cells come in rank order, i.e. global triangle order, each with its original corners.
  vtkNew<vtkIdList> corners;
  for (vtkIdType c = 0; c < surface.GetNumberOfCells(); ++c) {
    ASSERT_EQ(id->GetTuple1(c), static_cast<double>(c));
    EXPECT_EQ(rank->GetTuple1(c), static_cast<double>(c % 7));
    surface.GetCellPoints(c, corners);
    ASSERT_EQ(corners->GetNumberOfIds(), 3);
    const auto expected = GridSurface::triangle(static_cast<int>(c));
    for (int k = 0; k < 3; ++k) {
      double pos[3];
      surface.GetPoint(corners->GetId(k), pos);
      const auto want = GridSurface::position(expected[k]);
      EXPECT_EQ(pos[0], want[0]);
      EXPECT_EQ(pos[1], want[1]);
    }
  }
}

class ParallelSurfaceWriter : public ::testing::TestWithParam<SurfaceFormat> {};

TEST_P(ParallelSurfaceWriter, PiecesReadBackAsTheWholeSurface) {
  const auto comm = par::world();
  const auto dir = test::scratch_dir("parallel_surface");
  const auto [first, last] = triangle_range(comm);
  const OwnedPiece owned(first, last);
  const auto path = write_parallel_surface(comm, dir, "surface", owned.piece(), GetParam());
  EXPECT_EQ(path, dir / (std::string("surface.p") + surface_extension(GetParam())));

  std::uint64_t points = owned.xyz.size() / 3, total_points = 0;
  MPI_Allreduce(&points, &total_points, 1, MPI_UINT64_T, MPI_SUM, comm.raw);
  if (comm.is_root()) {
    const auto surface = read_back(path, GetParam());
    ASSERT_TRUE(surface);
    EXPECT_EQ(static_cast<std::uint64_t>(surface->GetNumberOfPoints()), total_points);
    expect_whole_surface(*surface);
    EXPECT_TRUE(test::temporary_files_under(dir).empty());
  }
  comm.barrier();
}

TEST_P(ParallelSurfaceWriter, AFailureOnOneRankIsAnErrorOnEveryRank) {
  const auto comm = par::world();
  const auto dir = test::scratch_dir("parallel_surface_failure");
  const OwnedPiece owned(0, 4);
  auto broken = owned.piece();
  if (comm.rank == comm.size - 1)
    broken.point_fields[0].values = std::span<const double>(owned.height).first(1);
  EXPECT_THROW(write_parallel_surface(comm, dir, "broken", broken, GetParam()), Error);

  // The header declares one type per field: ranks disagreeing on it is an error too.
  if (comm.size > 1) {
    auto retyped = owned.piece();
    const std::vector<std::int64_t> wide(owned.rank.begin(), owned.rank.end());
    if (comm.is_root())
      retyped.cell_fields[1].values = std::span<const std::int64_t>(wide);
    EXPECT_THROW(write_parallel_surface(comm, dir, "retyped", retyped, GetParam()), Error);
  }

  const auto blocker = dir / "not_a_directory";
  if (comm.is_root())
    std::ofstream(blocker) << "a file";
  comm.barrier();
  EXPECT_THROW(write_parallel_surface(comm, blocker, "s", owned.piece(), GetParam()), Error);
}

INSTANTIATE_TEST_SUITE_P(Formats, ParallelSurfaceWriter,
                         ::testing::Values(SurfaceFormat::vtp, SurfaceFormat::vtu),
                         [](const auto& info) { return surface_extension(info.param); });

} // namespace
} // namespace texsim::io
