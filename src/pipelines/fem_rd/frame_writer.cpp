#include "pipelines/fem_rd/frame_writer.hpp"

#include "io/parallel_surface_writer.hpp"

namespace texsim::pipelines::fem_rd {

std::filesystem::path write_frame(const par::Comm& comm, const geom::DistributedMesh& mesh,
                                  const ReactionDiffusionSolver& solver,
                                  const std::filesystem::path& dir, const std::string& basename) {
  // Points of this piece: the local vertices used by the owned triangles, in first-use order.
  std::vector<std::int32_t> piece_index(mesh.local_count(), -1);
  std::vector<std::int32_t> piece_locals;
  std::vector<std::int64_t> triangles;
  for (const std::int32_t t : mesh.owned_triangles())
    for (const std::int32_t local : mesh.mesh().triangles[t]) {
      if (piece_index[local] < 0) {
        piece_index[local] = std::int32_t(piece_locals.size());
        piece_locals.push_back(local);
      }
      triangles.push_back(piece_index[local]);
    }
  const std::size_t n = piece_locals.size();
  std::vector<double> xyz(3 * n);
  std::vector<std::int64_t> input_id(n);
  std::vector<std::vector<double>> species(solver.species_count(), std::vector<double>(n));
  const auto points = solver.surface_points();
  std::vector<std::vector<double>> values;
  for (std::size_t s = 0; s < species.size(); ++s)
    values.push_back(solver.surface_values(s));
  for (std::size_t p = 0; p < n; ++p) {
    const std::int32_t local = piece_locals[p];
    for (int axis = 0; axis < 3; ++axis)
      xyz[3 * p + axis] = points[std::size_t(local)][axis];
    input_id[p] = mesh.input_id()[local];
    for (std::size_t s = 0; s < species.size(); ++s)
      species[s][p] = values[s][std::size_t(local)];
  }
  const std::vector<std::int32_t> owner(mesh.owned_triangles().size(), comm.rank);
  io::SurfacePiece piece{xyz, triangles, {}, {{"rank", 1, owner}}};
  for (std::size_t s = 0; s < species.size(); ++s)
    piece.point_fields.push_back({solver.species_names()[s], 1, species[s]});
  piece.point_fields.push_back({"input_vertex_id", 1, input_id});
  return io::write_parallel_surface(comm, dir, basename, piece, io::SurfaceFormat::vtu);
}

} // namespace texsim::pipelines::fem_rd
