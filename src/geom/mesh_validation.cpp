#include "geom/mesh_validation.hpp"

#include "core/error.hpp"
#include "geom/mesh_measures.hpp"
#include "geom/mesh_repair.hpp"
#include "geom/mesh_topology.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <tuple>
#include <utility>

namespace texsim::geom {
namespace {

template <class Describe> void note(MeshIssue& issue, Describe&& describe) {
  if (issue.count++ == 0) {
    std::ostringstream out;
    describe(out);
    issue.first = out.str();
  }
}

std::ostream& operator<<(std::ostream& out, const Triangle& tri) {
  return out << "(" << tri[0] << ", " << tri[1] << ", " << tri[2] << ")";
}

MeshIssue find_non_finite(const TriangleMesh& mesh) {
  MeshIssue issue;
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    const auto& p = mesh.positions[v];
    if (!p.allFinite()) {
      note(issue, [&](std::ostream& out) {
        out << "vertex " << v << " at (" << p.x() << ", " << p.y() << ", " << p.z() << ")";
      });
    }
  }
  return issue;
}

MeshIssue find_out_of_range(const TriangleMesh& mesh) {
  MeshIssue issue;
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (std::any_of(tri.begin(), tri.end(),
                    [&](std::int32_t v) { return v < 0 || v >= mesh.num_vertices(); })) {
      note(issue, [&](std::ostream& out) {
        out << "triangle " << t << " " << tri << " with " << mesh.num_vertices() << " vertices";
      });
    }
  }
  return issue;
}

/// Per triangle: degenerate by a repeated index or an area at most tolerance * mean edge^2.
std::vector<char> degenerate_flags(const TriangleMesh& mesh, double tolerance, MeshIssue& issue) {
  const double edge = mean_edge_length(mesh);
  const double min_area = tolerance * edge * edge;
  std::vector<char> flags(mesh.triangles.size(), 0);
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    const auto& tri = mesh.triangles[t];
    const bool repeated = tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2];
    const double area = repeated ? 0.0
                                 : triangle_area(mesh.positions[tri[0]], mesh.positions[tri[1]],
                                                 mesh.positions[tri[2]]);
    if (repeated || area <= min_area) {
      flags[t] = 1;
      note(issue, [&](std::ostream& out) {
        out << "triangle " << t << " " << tri
            << (repeated ? " repeats a vertex" : " has zero area");
      });
    }
  }
  return flags;
}

/// Per triangle: its vertex set equals that of an earlier triangle.
std::vector<char> duplicate_flags(const TriangleMesh& mesh, MeshIssue& issue) {
  std::vector<std::pair<Triangle, std::int32_t>> sorted(mesh.triangles.size());
  for (std::int32_t t = 0; t < mesh.num_triangles(); ++t) {
    auto key = mesh.triangles[t];
    std::sort(key.begin(), key.end());
    sorted[t] = {key, t};
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::pair<std::int32_t, std::int32_t>> repeats; // (triangle, its first twin)
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i].first == sorted[i - 1].first) {
      const auto twin = repeats.empty() || repeats.back().first != sorted[i - 1].second
                            ? sorted[i - 1].second
                            : repeats.back().second;
      repeats.emplace_back(sorted[i].second, twin);
    }
  }
  std::sort(repeats.begin(), repeats.end());
  std::vector<char> flags(mesh.triangles.size(), 0);
  for (const auto& [t, twin] : repeats) {
    flags[t] = 1;
    note(issue, [&](std::ostream& out) {
      out << "triangle " << t << " " << mesh.triangles[t] << " repeats triangle " << twin;
    });
  }
  return flags;
}

std::vector<char> referenced_flags(const TriangleMesh& mesh) {
  std::vector<char> used(mesh.positions.size(), 0);
  for (const auto& tri : mesh.triangles) {
    for (const auto v : tri) {
      used[v] = 1;
    }
  }
  return used;
}

MeshIssue find_non_manifold_edges(const MeshTopology& topo) {
  MeshIssue issue;
  for (const auto e : topo.non_manifold_edges()) {
    note(issue, [&](std::ostream& out) {
      out << "vertices " << topo.edges()[e][0] << "-" << topo.edges()[e][1] << " shared by "
          << topo.edge_triangles(e).size() << " triangles";
    });
  }
  return issue;
}

/// True when triangle tri walks from a directly to b.
bool walks(const Triangle& tri, std::int32_t a, std::int32_t b) {
  for (int i = 0; i < 3; ++i) {
    if (tri[i] == a && tri[(i + 1) % 3] == b) {
      return true;
    }
  }
  return false;
}

template <class Keep> void keep_triangles(TriangleMesh& mesh, Keep&& keep) {
  std::size_t out = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (keep(t)) {
      mesh.triangles[out++] = mesh.triangles[t];
    }
  }
  mesh.triangles.resize(out);
}

std::size_t merge_coincident(TriangleMesh& mesh) {
  std::vector<std::int32_t> order(mesh.positions.size());
  std::iota(order.begin(), order.end(), 0);
  const auto less = [&](std::int32_t a, std::int32_t b) {
    const auto& p = mesh.positions[a];
    const auto& q = mesh.positions[b];
    return std::tie(p.x(), p.y(), p.z(), a) < std::tie(q.x(), q.y(), q.z(), b);
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::int32_t> representative(mesh.positions.size());
  std::size_t merged = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const bool same = i > 0 && mesh.positions[order[i]] == mesh.positions[order[i - 1]];
    representative[order[i]] = same ? representative[order[i - 1]] : order[i];
    merged += same ? 1 : 0;
  }
  for (auto& tri : mesh.triangles) {
    for (auto& v : tri) {
      v = representative[v];
    }
  }
  return merged;
}

std::size_t drop_unreferenced(TriangleMesh& mesh) {
  const auto used = referenced_flags(mesh);
  std::vector<std::int32_t> new_id(mesh.positions.size(), -1);
  std::int32_t next = 0;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (used[v]) {
      mesh.positions[next] = mesh.positions[v];
      new_id[v] = next++;
    }
  }
  const std::size_t dropped = mesh.positions.size() - static_cast<std::size_t>(next);
  mesh.positions.resize(next);
  for (auto& tri : mesh.triangles) {
    for (auto& v : tri) {
      v = new_id[v];
    }
  }
  return dropped;
}

[[noreturn]] void refuse(const std::string& source, const MeshIssue& issue, const char* what,
                         const char* expected) {
  TEXSIM_INPUT_ERROR(source << ": " << issue.count << " " << what << " (first: " << issue.first
                            << "); " << expected);
}

} // namespace

MeshIssue inconsistent_orientation(const TriangleMesh& mesh, const MeshTopology& topo) {
  MeshIssue issue;
  for (std::int32_t e = 0; e < topo.num_edges(); ++e) {
    const auto around = topo.edge_triangles(e);
    const auto [a, b] = topo.edges()[e];
    if (around.size() == 2 && a != b &&
        walks(mesh.triangles[around[0]], a, b) == walks(mesh.triangles[around[1]], a, b)) {
      note(issue, [&](std::ostream& out) {
        out << "edge " << a << "-" << b << " of triangles " << around[0] << " and " << around[1];
      });
    }
  }
  return issue;
}

bool MeshReport::clean() const {
  return !non_finite_vertices && !out_of_range_indices && !degenerate_triangles &&
         !duplicate_triangles && !unreferenced_vertices && !non_manifold_edges &&
         !non_manifold_vertices && !inconsistent_orientation;
}

bool RepairReport::changed() const {
  return merged_vertices + dropped_degenerate_triangles + dropped_duplicate_triangles +
             dropped_unreferenced_vertices + split_added_vertices + reoriented_triangles +
             dropped_components + filled_holes >
         0;
}

std::string RepairReport::summary() const {
  if (!changed()) {
    return "no repairs";
  }
  const std::pair<std::size_t, const char*> items[] = {
      {merged_vertices, "merged coincident vertices"},
      {dropped_degenerate_triangles, "dropped degenerate triangles"},
      {dropped_duplicate_triangles, "dropped duplicate triangles"},
      {non_manifold_edges, "split non-manifold edges"},
      {non_manifold_vertices, "split non-manifold vertices"},
      {split_added_vertices, "vertex copies added"},
      {reoriented_triangles, "reoriented triangles"},
      {dropped_components, "dropped small components"},
      {dropped_component_triangles, "their triangles"},
      {filled_holes, "filled holes"},
      {hole_triangles, "hole triangles added"},
      {dropped_unreferenced_vertices, "dropped unreferenced vertices"}};
  std::ostringstream out;
  const char* separator = "";
  for (const auto& [count, what] : items) {
    if (count > 0) {
      out << separator << what << ": " << count;
      separator = ", ";
    }
  }
  return out.str();
}

nlohmann::json RepairReport::metrics() const {
  return {{"merged_vertices", merged_vertices},
          {"dropped_degenerate_triangles", dropped_degenerate_triangles},
          {"dropped_duplicate_triangles", dropped_duplicate_triangles},
          {"dropped_unreferenced_vertices", dropped_unreferenced_vertices},
          {"non_manifold_edges", non_manifold_edges},
          {"non_manifold_vertices", non_manifold_vertices},
          {"inconsistent_orientation_edges", inconsistent_orientation_edges},
          {"split_added_vertices", split_added_vertices},
          {"reoriented_triangles", reoriented_triangles},
          {"components", components},
          {"dropped_components", dropped_components},
          {"dropped_component_triangles", dropped_component_triangles},
          {"filled_holes", filled_holes},
          {"hole_triangles", hole_triangles}};
}

MeshReport validate(const TriangleMesh& mesh, double degenerate_area_tolerance) {
  MeshReport report;
  report.non_finite_vertices = find_non_finite(mesh);
  report.out_of_range_indices = find_out_of_range(mesh);
  if (report.out_of_range_indices) {
    return report;
  }
  degenerate_flags(mesh, degenerate_area_tolerance, report.degenerate_triangles);
  duplicate_flags(mesh, report.duplicate_triangles);
  const auto used = referenced_flags(mesh);
  for (std::int32_t v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[v]) {
      note(report.unreferenced_vertices, [&](std::ostream& out) { out << "vertex " << v; });
    }
  }
  const MeshTopology topo(mesh);
  report.non_manifold_edges = find_non_manifold_edges(topo);
  for (const auto v : topo.non_manifold_vertices()) {
    note(report.non_manifold_vertices, [&](std::ostream& out) { out << "vertex " << v; });
  }
  report.inconsistent_orientation = inconsistent_orientation(mesh, topo);
  report.boundary_edges = topo.boundary_edges().size();
  return report;
}

namespace {

/// Appends "N what (first: ...)" to `found` when the issue occurred.
void list_issue(std::vector<std::string>& found, const MeshIssue& issue, const char* what) {
  if (issue)
    found.push_back(std::to_string(issue.count) + " " + what + " (first: " + issue.first + ")");
}

/// Strict mode: refuses, listing every defect that `fix` would repair.
void refuse_defects(const TriangleMesh& mesh, const MeshRepairOptions& options,
                    const std::string& source_name) {
  const auto report = validate(mesh, options.degenerate_area_tolerance);
  std::vector<std::string> found;
  list_issue(found, report.degenerate_triangles, "degenerate triangles");
  list_issue(found, report.duplicate_triangles, "duplicate triangles");
  list_issue(found, report.non_manifold_edges, "non-manifold edges");
  list_issue(found, report.non_manifold_vertices, "non-manifold vertices");
  list_issue(found, report.inconsistent_orientation, "inconsistently oriented edges");
  if (found.empty() && options.min_component_fraction > 0) {
    auto copy = mesh;
    const auto drop = drop_small_components(copy, options.min_component_fraction);
    if (drop.dropped_components > 0)
      found.push_back(
          std::to_string(drop.dropped_components) + " of " + std::to_string(drop.components) +
          " connected components below min_component_fraction " +
          std::to_string(options.min_component_fraction) + " of the largest one's area (" +
          std::to_string(drop.dropped_triangles) + " triangles)");
  }
  if (found.empty())
    return;
  std::ostringstream message;
  message << source_name << ": the mesh needs repair (mesh.repair: strict): ";
  for (std::size_t i = 0; i < found.size(); ++i)
    message << (i ? "; " : "") << found[i];
  message << "; expected a clean manifold surface, or mesh.repair: fix";
  throw InputError(message.str());
}

/// Cuts non-manifold edges and vertices apart and orients, recording what was found.
void split_and_orient(TriangleMesh& mesh, RepairReport& report) {
  const MeshTopology topo(mesh);
  report.non_manifold_edges = topo.non_manifold_edges().size();
  report.non_manifold_vertices = topo.non_manifold_vertices().size();
  report.inconsistent_orientation_edges = inconsistent_orientation(mesh, topo).count;
  if (report.non_manifold_edges + report.non_manifold_vertices +
          report.inconsistent_orientation_edges ==
      0)
    return;
  const auto split = split_non_manifold(mesh);
  report.split_added_vertices = split.added_vertices;
  report.reoriented_triangles = split.reoriented_triangles;
}

} // namespace

RepairReport repair(TriangleMesh& mesh, const MeshRepairOptions& options,
                    const std::string& source_name) {
  if (mesh.triangles.empty()) {
    TEXSIM_INPUT_ERROR(source_name << ": no triangles (" << mesh.positions.size()
                                   << " vertices); expected a triangle surface");
  }
  if (const auto issue = find_non_finite(mesh)) {
    refuse(source_name, issue, "vertices with a non-finite coordinate",
           "expected finite coordinates");
  }
  if (const auto issue = find_out_of_range(mesh)) {
    refuse(source_name, issue, "triangles with a vertex index out of range",
           "expected indices of listed vertices");
  }
  RepairReport report;
  if (options.merge_coincident_vertices) {
    report.merged_vertices = merge_coincident(mesh);
  }
  if (options.strict) {
    refuse_defects(mesh, options, source_name);
  }
  if (options.drop_degenerate_triangles) {
    MeshIssue issue;
    const auto flags = degenerate_flags(mesh, options.degenerate_area_tolerance, issue);
    keep_triangles(mesh, [&](std::size_t t) { return !flags[t]; });
    report.dropped_degenerate_triangles = issue.count;
  }
  if (options.drop_duplicate_triangles) {
    MeshIssue issue;
    const auto flags = duplicate_flags(mesh, issue);
    keep_triangles(mesh, [&](std::size_t t) { return !flags[t]; });
    report.dropped_duplicate_triangles = issue.count;
  }
  if (options.drop_unreferenced_vertices) {
    report.dropped_unreferenced_vertices = drop_unreferenced(mesh);
  }
  if (mesh.triangles.empty()) {
    TEXSIM_INPUT_ERROR(source_name << ": no usable triangles left after repair ("
                                   << report.summary() << "); expected a triangle surface");
  }
  if (options.split_non_manifold) {
    split_and_orient(mesh, report);
  } else if (options.require_manifold_edges) {
    if (const auto issue = find_non_manifold_edges(MeshTopology(mesh))) {
      refuse(source_name, issue, "non-manifold edges", "texsim needs a manifold surface");
    }
  }
  if (options.min_component_fraction > 0) {
    const auto drop = drop_small_components(mesh, options.min_component_fraction);
    report.components = drop.components;
    report.dropped_components = drop.dropped_components;
    report.dropped_component_triangles = drop.dropped_triangles;
    report.dropped_unreferenced_vertices += drop_unreferenced(mesh);
  }
  if (options.fill_holes) {
    const auto fill = fill_holes(mesh);
    report.filled_holes = fill.holes;
    report.hole_triangles = fill.added_triangles;
  }
  return report;
}

} // namespace texsim::geom
