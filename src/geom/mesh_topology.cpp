#include "geom/mesh_topology.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

namespace texsim::geom {
namespace {

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

/// Finds the root of i with path halving.
std::int32_t find_root(std::vector<std::int32_t>& parent, std::int32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

/// Number of edge-connected fans among the triangles around vertex v.
int count_fans(const MeshTopology& topo, const std::vector<Triangle>& triangles, std::int32_t v) {
  const auto around = topo.vertex_triangles().row(v);
  std::vector<std::int32_t> parent(around.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto local = [&](std::int32_t t) {
    return static_cast<std::int32_t>(std::find(around.begin(), around.end(), t) - around.begin());
  };
  int fans = static_cast<int>(around.size());
  for (std::size_t i = 0; i < around.size(); ++i) {
    const auto t = around[i];
    for (int corner = 0; corner < 3; ++corner) {
      if (triangles[t][corner] == v) {
        continue;
      }
      // The edge opposite a corner that is not v contains v.
      for (const auto other : topo.edge_triangles(topo.triangle_edges(t)[corner])) {
        const auto a = find_root(parent, static_cast<std::int32_t>(i));
        const auto b = find_root(parent, local(other));
        if (a != b) {
          parent[a] = b;
          --fans;
        }
      }
    }
  }
  return fans;
}

} // namespace

MeshTopology::MeshTopology(const TriangleMesh& mesh) {
  const auto n_vertices = mesh.num_vertices();
  const auto n_triangles = mesh.num_triangles();
  for (const auto& tri : mesh.triangles) {
    for (const auto v : tri) {
      TEXSIM_VERIFY(v >= 0 && v < n_vertices, "MeshTopology: vertex index "
                                                  << v << " out of range [0, " << n_vertices
                                                  << ")");
    }
  }

  // Edges: one (key, side) record per triangle side, ordered by key and then by side, so equal
  // edges are adjacent. A counting sort by the smaller vertex puts the records into one short
  // bucket per vertex, in side order; each bucket is then ordered by the larger vertex (stable:
  // insertion, as a bucket holds about six records). That is the order a sort of all 3T records
  // gives, in linear time (a global sort was the largest cost of this constructor).
  std::vector<std::int64_t> bucket_start(static_cast<std::size_t>(n_vertices) + 1, 0);
  for (const auto& tri : mesh.triangles)
    for (int corner = 0; corner < 3; ++corner)
      ++bucket_start[std::min(tri[(corner + 1) % 3], tri[(corner + 2) % 3]) + 1];
  std::partial_sum(bucket_start.begin(), bucket_start.end(), bucket_start.begin());
  std::vector<std::pair<std::uint64_t, std::int64_t>> sides(3 *
                                                            static_cast<std::size_t>(n_triangles));
  {
    std::vector<std::int64_t> next(bucket_start.begin(), bucket_start.end() - 1);
    for (std::int32_t t = 0; t < n_triangles; ++t) {
      const auto& tri = mesh.triangles[t];
      for (int corner = 0; corner < 3; ++corner) {
        const std::int32_t a = tri[(corner + 1) % 3], b = tri[(corner + 2) % 3];
        sides[next[std::min(a, b)]++] = {edge_key(a, b), std::int64_t{3} * t + corner};
      }
    }
  }
  const auto by_key = [](const auto& x, const auto& y) { return x.first < y.first; };
  for (std::int32_t v = 0; v < n_vertices; ++v) {
    const auto first = sides.begin() + bucket_start[v], last = sides.begin() + bucket_start[v + 1];
    if (last - first > 32) { // a hub vertex (a fan in a raw scan): no quadratic insertion
      std::stable_sort(first, last, by_key);
      continue;
    }
    for (auto i = first + 1; i < last; ++i) {
      const auto record = *i;
      auto j = i;
      for (; j > first && by_key(record, *(j - 1)); --j)
        *j = *(j - 1);
      *j = record;
    }
  }

  triangle_edges_.resize(n_triangles);
  edge_triangles_.offsets.push_back(0);
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const auto [key, side] = sides[i];
    const bool new_edge = i == 0 || sides[i - 1].first != key;
    if (new_edge) {
      if (i > 0) {
        edge_triangles_.offsets.push_back(
            static_cast<std::int64_t>(edge_triangles_.indices.size()));
      }
      edges_.push_back(
          {static_cast<std::int32_t>(key >> 32), static_cast<std::int32_t>(key & 0xffffffffu)});
    }
    const auto t = static_cast<std::int32_t>(side / 3);
    triangle_edges_[t][side % 3] = num_edges() - 1;
    const auto begin = edge_triangles_.offsets.back();
    const bool repeated = static_cast<std::int64_t>(edge_triangles_.indices.size()) > begin &&
                          edge_triangles_.indices.back() == t;
    if (!repeated) {
      edge_triangles_.indices.push_back(t);
    }
  }
  edge_triangles_.offsets.push_back(static_cast<std::int64_t>(edge_triangles_.indices.size()));

  // Vertex -> triangles: count, prefix sum, fill in increasing triangle order.
  auto& vt = vertex_triangles_;
  vt.offsets.assign(static_cast<std::size_t>(n_vertices) + 1, 0);
  const auto distinct_corners = [](const Triangle& tri, int corner) {
    for (int earlier = 0; earlier < corner; ++earlier) {
      if (tri[earlier] == tri[corner]) {
        return false;
      }
    }
    return true;
  };
  for (const auto& tri : mesh.triangles) {
    for (int corner = 0; corner < 3; ++corner) {
      if (distinct_corners(tri, corner)) {
        ++vt.offsets[tri[corner] + 1];
      }
    }
  }
  std::partial_sum(vt.offsets.begin(), vt.offsets.end(), vt.offsets.begin());
  vt.indices.resize(vt.offsets.back());
  std::vector<std::int64_t> cursor(vt.offsets.begin(), vt.offsets.end() - 1);
  for (std::int32_t t = 0; t < n_triangles; ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      if (distinct_corners(mesh.triangles[t], corner)) {
        vt.indices[cursor[mesh.triangles[t][corner]]++] = t;
      }
    }
  }

  // Vertex -> neighbours from the edges (self-loops of degenerate triangles skipped).
  auto& vn = vertex_neighbors_;
  vn.offsets.assign(static_cast<std::size_t>(n_vertices) + 1, 0);
  for (const auto& [a, b] : edges_) {
    if (a != b) {
      ++vn.offsets[a + 1];
      ++vn.offsets[b + 1];
    }
  }
  std::partial_sum(vn.offsets.begin(), vn.offsets.end(), vn.offsets.begin());
  vn.indices.resize(vn.offsets.back());
  cursor.assign(vn.offsets.begin(), vn.offsets.end() - 1);
  for (const auto& [a, b] : edges_) {
    if (a != b) {
      vn.indices[cursor[a]++] = b;
      vn.indices[cursor[b]++] = a;
    }
  }
  for (std::int32_t v = 0; v < n_vertices; ++v) {
    std::sort(vn.indices.begin() + vn.offsets[v], vn.indices.begin() + vn.offsets[v + 1]);
  }

  // Boundary and non-manifold edges.
  std::vector<char> on_boundary(n_vertices, 0);
  for (std::int32_t e = 0; e < num_edges(); ++e) {
    const auto count = edge_triangles(e).size();
    if (count == 1) {
      boundary_edges_.push_back(e);
      on_boundary[edges_[e][0]] = on_boundary[edges_[e][1]] = 1;
    } else if (count > 2) {
      non_manifold_edges_.push_back(e);
    }
  }
  for (std::int32_t v = 0; v < n_vertices; ++v) {
    if (on_boundary[v]) {
      boundary_vertices_.push_back(v);
    }
    if (vt.row(v).empty()) {
      isolated_vertices_.push_back(v);
    } else if (count_fans(*this, mesh.triangles, v) > 1) {
      non_manifold_vertices_.push_back(v);
    }
  }
}

std::int32_t MeshTopology::find_edge(std::int32_t a, std::int32_t b) const {
  const Edge target{std::min(a, b), std::max(a, b)};
  const auto it = std::lower_bound(edges_.begin(), edges_.end(), target);
  return it != edges_.end() && *it == target ? static_cast<std::int32_t>(it - edges_.begin()) : -1;
}

} // namespace texsim::geom
