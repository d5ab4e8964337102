#include "geom/distributed_noise.hpp"

#include "core/rng.hpp"
#include "geom/distributed_measures.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"

#include <vector>

namespace texsim::geom {

void add_normal_noise(DistributedMesh& mesh, double amplitude, std::uint64_t seed) {
  const double scaled = amplitude * mean_edge_length(mesh);
  const CounterRng rng(seed, kNoisyMeshStream);
  // Owned vertices hold all their triangles, so their normals are the whole surface's.
  const auto normals = vertex_normals(mesh.mesh());
  const auto& positions = mesh.mesh().positions;
  std::vector<double> owned_xyz(3 * std::size_t(mesh.owned_count()));
  for (std::int32_t v = 0; v < mesh.owned_count(); ++v) {
    const double draw = rng.uniform(-1.0, 1.0, static_cast<std::uint64_t>(mesh.input_id()[v]), 0);
    const Vec3 moved = positions[v] + scaled * draw * normals[v];
    for (int k = 0; k < 3; ++k)
      owned_xyz[3 * std::size_t(v) + std::size_t(k)] = moved[k];
  }
  mesh.set_owned_positions(owned_xyz);
}

} // namespace texsim::geom
