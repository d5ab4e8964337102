#include "core/rng.hpp"
#include "geom/generators.hpp"
#include "geom/mesh_measures.hpp"

namespace texsim::geom {

TriangleMesh noisy(const TriangleMesh& mesh, double amplitude, std::uint64_t seed) {
  const CounterRng rng(seed, kNoisyMeshStream);
  const auto normals = vertex_normals(mesh);
  TriangleMesh out = mesh;
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    out.positions[v] +=
        amplitude * rng.uniform(-1.0, 1.0, static_cast<std::uint64_t>(v), 0) * normals[v];
  }
  return out;
}

} // namespace texsim::geom
