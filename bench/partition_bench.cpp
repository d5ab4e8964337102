// Edge cut and balance of the two vertex partitions fem_rd offers, Scotch's sequential strategy
// (the default) and the Morton curve, on real meshes for several part counts, with the time each
// takes. Partitions are computed on one process for any part count (both are pure functions of
// the mesh and the part count), so 64 parts need no 64 ranks.
// Usage: partition_bench MESH.off [MESH ...] [--parts 2,3,8,64]   (prints one JSON object)
#include "bench_timing.hpp"
#include "geom/mesh_reader.hpp"
#include "geom/mesh_topology.hpp"
#include "par/graph_partition.hpp"
#include "par/morton_partition.hpp"
#include "par/petsc_session.hpp"

#include <nlohmann/json.hpp>

#include <iostream>
#include <sstream>

namespace {
using namespace texsim;

struct Cut {
  std::int64_t edge_cut = 0;
  double imbalance = 0;
};

Cut measure(const geom::MeshTopology& topology, const std::vector<int>& part, int parts) {
  Cut cut;
  for (const auto& edge : topology.edges())
    cut.edge_cut += part[std::size_t(edge[0])] != part[std::size_t(edge[1])];
  std::vector<std::int64_t> counts(std::size_t(parts), 0);
  for (const int p : part)
    ++counts[std::size_t(p)];
  cut.imbalance = double(*std::max_element(counts.begin(), counts.end())) * parts / part.size();
  return cut;
}

std::vector<int> parse_parts(const std::string& list) {
  std::vector<int> parts;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');)
    parts.push_back(std::stoi(item));
  return parts;
}

} // namespace

int main(int argc, char** argv) {
  par::PetscSession session(argc, argv);
  const par::Comm self{MPI_COMM_SELF, 0, 1};
  std::vector<std::string> meshes;
  std::vector<int> part_counts{2, 3, 8, 64};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--parts" && i + 1 < argc)
      part_counts = parse_parts(argv[++i]);
    else
      meshes.push_back(arg);
  }
  nlohmann::json result{{"benchmark", "partition"}, {"meshes", nlohmann::json::object()}};
  for (const auto& path : meshes) {
    const geom::TriangleMesh mesh = geom::read_mesh(path);
    const geom::MeshTopology topology(mesh);
    std::vector<std::array<double, 3>> points;
    for (const auto& p : mesh.positions)
      points.push_back({p.x(), p.y(), p.z()});
    const auto& graph = topology.vertex_neighbors();
    nlohmann::json rows = nlohmann::json::array();
    for (const int parts : part_counts) {
      std::vector<int> scotch, morton;
      const double scotch_s = bench::timed(self, [&] {
        scotch = par::scotch_graph_partition(self, graph.offsets, graph.indices, parts);
      });
      const double morton_s =
          bench::timed(self, [&] { morton = par::morton_partition(points, parts); });
      const Cut s = measure(topology, scotch, parts), m = measure(topology, morton, parts);
      rows.push_back(
          {{"parts", parts},
           {"scotch",
            {{"edge_cut", s.edge_cut}, {"imbalance", s.imbalance}, {"seconds", scotch_s}}},
           {"morton",
            {{"edge_cut", m.edge_cut}, {"imbalance", m.imbalance}, {"seconds", morton_s}}},
           {"cut_ratio_scotch_over_morton", double(s.edge_cut) / double(m.edge_cut)}});
    }
    result["meshes"][path] = {{"vertices", mesh.num_vertices()},
                              {"edges", topology.edges().size()},
                              {"partitions", rows}};
  }
  std::cout << result.dump(1) << std::endl;
  return 0;
}
