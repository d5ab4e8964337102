// turk_rd's render mesh is Loop-refined on each rank's share of the input only: over all ranks
// every fine triangle of the whole input's refinement is written exactly once, with the same
// position bits, and each piece's ring holds the triangles around its written ones, also bit for
// bit. At 1, 2 and 3 ranks, on a noisy sphere, an open noisy square (boundary masks), a noisy cube
// with creases and the raw bunny with its holes.
#include "geom/crease_edges.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_topology.hpp"
#include "geom/patch_refinement.hpp"
#include "par/record_exchange.hpp"
#include "pipelines/turk_rd/render_piece.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <span>
#include <vector>

namespace texsim::pipelines::turk_rd {
namespace {

/// A triangle as its corners' coordinates, started at the smallest corner (orientation kept).
using PlacedTriangle = std::array<double, 9>;

PlacedTriangle placed(const geom::TriangleMesh& mesh, const geom::Triangle& triangle) {
  std::array<std::array<double, 3>, 3> corners{};
  for (int c = 0; c < 3; ++c)
    for (int a = 0; a < 3; ++a)
      corners[c][a] = mesh.positions[triangle[c]][a];
  const int first = int(std::min_element(corners.begin(), corners.end()) - corners.begin());
  PlacedTriangle out{};
  for (int c = 0; c < 3; ++c)
    for (int a = 0; a < 3; ++a)
      out[3 * c + a] = corners[(first + c) % 3][a];
  return out;
}

void check_pieces(const geom::TriangleMesh& input, int levels, std::span<const char> creases = {}) {
  const par::Comm comm = par::world();
  // Split from rank 0, as turk_rd does: each rank sees its share and the window it fetches.
  const RenderPiece piece = make_render_piece(
      comm,
      geom::DistributedTriangles::from_root(comm, comm.is_root() ? input : geom::TriangleMesh{},
                                            comm.is_root() ? creases : std::span<const char>()),
      levels);
  std::vector<PlacedTriangle> mine;
  for (std::size_t t = 0; t < piece.written_triangles; ++t)
    mine.push_back(placed(piece.mesh, piece.mesh.triangles[t]));
  ASSERT_EQ(piece.written_connectivity.size(), 3 * piece.written_triangles);
  for (std::size_t k = 0; k < piece.written_connectivity.size(); ++k)
    ASSERT_EQ(piece.written_vertices[std::size_t(piece.written_connectivity[k])],
              piece.mesh.triangles[k / 3][k % 3]);
  // The ring: every triangle of the fine mesh around a written vertex is in the piece.
  const geom::TriangleMesh whole =
      geom::refine(input, std::vector<geom::RefinementStep>(std::size_t(levels)), creases);
  const geom::MeshTopology whole_topology(whole);
  const geom::MeshTopology piece_topology(piece.mesh);
  std::map<std::array<double, 3>, std::size_t> fan_of; // triangles around each fine vertex
  for (std::int32_t v = 0; v < whole.num_vertices(); ++v)
    fan_of[{whole.positions[v].x(), whole.positions[v].y(), whole.positions[v].z()}] =
        whole_topology.vertex_triangles().row(v).size();
  for (const std::int32_t v : piece.written_vertices) {
    const auto& p = piece.mesh.positions[v];
    ASSERT_EQ(piece_topology.vertex_triangles().row(v).size(), fan_of.at({p.x(), p.y(), p.z()}));
  }
  auto all = par::allgather_records(comm, mine);
  std::vector<PlacedTriangle> expected;
  for (const auto& triangle : whole.triangles)
    expected.push_back(placed(whole, triangle));
  std::sort(all.begin(), all.end());
  std::sort(expected.begin(), expected.end());
  // The ring's triangles too are the whole surface's, bit for bit (the normals at the border).
  for (std::size_t t = piece.written_triangles; t < piece.mesh.triangles.size(); ++t)
    ASSERT_TRUE(std::binary_search(expected.begin(), expected.end(),
                                   placed(piece.mesh, piece.mesh.triangles[t])))
        << "ring triangle " << t << " is not the subdivided surface's";
  EXPECT_EQ(all, expected) << levels << " levels on " << comm.size << " ranks";
}

TEST(RenderPiece, RefinedSharesMakeTheWholeSubdividedSurface) {
  const auto sphere = geom::noisy(geom::icosphere(2), 0.05, 4);
  const auto square = geom::noisy(geom::plane(geom::Vec3(1, 1, 0), 6), 0.05, 9);
  for (const int levels : {0, 1, 2}) {
    check_pieces(sphere, levels);
    check_pieces(square, levels);
  }
}

TEST(RenderPiece, CreasesStaySharpPieceByPiece) {
  // A cube's edges as creases (mesh.crease_angle): the pieces are the whole creased refinement's.
  const auto cube = geom::noisy(geom::box(geom::Vec3(1, 1, 1), 4), 0.03, 5);
  const auto creases = geom::crease_edges(cube, geom::MeshTopology(cube), 45.0);
  check_pieces(cube, 2, creases);
}

TEST(RenderPieceOnRealData, TheRawBunnyRefinesPieceByPiece) {
  const auto path = test::real_data("meshes/bunny00.off");
  if (path.empty())
    GTEST_SKIP() << test::missing_data_message("meshes/bunny00.off");
  check_pieces(geom::read_mesh(path), 1);
}

} // namespace
} // namespace texsim::pipelines::turk_rd
