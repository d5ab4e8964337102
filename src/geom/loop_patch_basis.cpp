#include "geom/loop_patch_basis.hpp"

#include "core/error.hpp"
#include "geom/loop_box_spline.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

namespace texsim::geom {
namespace {

using LocalTriangle = std::array<int, 3>;

/// A triangle with the stars of its corners, every vertex a combination of the original controls
/// (row v of `weights`), refined around the point being evaluated.
struct LocalPatch {
  std::vector<LocalTriangle> triangles;
  Eigen::MatrixXd weights;
  LocalTriangle corners{};
  std::set<std::pair<int, int>> creases; ///< crease edges (smaller vertex first)
};

int valence(const LocalPatch& patch, int v) {
  return int(std::count_if(patch.triangles.begin(), patch.triangles.end(), [v](const auto& tri) {
    return tri[0] == v || tri[1] == v || tri[2] == v;
  }));
}

/// The vertices sharing a triangle with v, increasing.
std::vector<int> neighbours(const LocalPatch& patch, int v) {
  std::vector<int> result;
  for (const auto& tri : patch.triangles)
    for (int k = 0; k < 3; ++k)
      if (tri[k] == v) {
        result.push_back(tri[(k + 1) % 3]);
        result.push_back(tri[(k + 2) % 3]);
      }
  std::sort(result.begin(), result.end());
  result.erase(std::unique(result.begin(), result.end()), result.end());
  return result;
}

/// Whether edge (v, w) at a corner is sharp: a crease, or on the surface's boundary (the corner's
/// star is whole in the patch, so an edge at it with one triangle lies on the boundary).
bool sharp(const LocalPatch& patch, int v, int w) {
  if (patch.creases.count(std::minmax(v, w)))
    return true;
  const auto shared = std::count_if(patch.triangles.begin(), patch.triangles.end(), [&](auto& t) {
    return std::count(t.begin(), t.end(), v) && std::count(t.begin(), t.end(), w);
  });
  return shared == 1;
}

/// The neighbours of corner v across its sharp edges.
std::vector<int> sharp_neighbours(const LocalPatch& patch, int v) {
  std::vector<int> found;
  for (const int w : neighbours(patch, v))
    if (sharp(patch, v, w))
      found.push_back(w);
  return found;
}

/// Three smooth interior corners of valence 6 (no sharp edge at them): one box spline (sharp
/// edges beyond the corners do not matter, since the masks that refine the patch read only the
/// corners' stars).
bool is_regular_patch(const LocalPatch& patch) {
  return std::all_of(patch.corners.begin(), patch.corners.end(), [&](int v) {
    return valence(patch, v) == 6 && sharp_neighbours(patch, v).empty();
  });
}

/// The third vertex of the triangle holding the directed edge y -> x, i.e. the vertex across the
/// edge x -> y of a triangle known to be counter-clockwise.
int across(const LocalPatch& patch, int x, int y) {
  for (const auto& tri : patch.triangles)
    for (int k = 0; k < 3; ++k)
      if (tri[k] == y && tri[(k + 1) % 3] == x)
        return tri[(k + 2) % 3];
  throw Error(
      "Loop basis: no triangle across an edge of a regular patch (inconsistent orientation)");
}

/// The local vertices at the 12 points of kRegularPatchLattice, walking from the corners across
/// edges.
std::array<int, 12> regular_lattice(const LocalPatch& patch) {
  const auto [a, b, c] = patch.corners;
  const int below = across(patch, a, b);  // (1, -1)
  const int beyond = across(patch, b, c); // (1, 1)
  const int left = across(patch, c, a);   // (-1, 1)
  return {a,
          b,
          c,
          left,
          across(patch, left, a),  // (-1, 0)
          across(patch, a, below), // (0, -1)
          below,
          across(patch, b, beyond), // (2, 0)
          beyond,
          across(patch, below, b),  // (2, -1)
          across(patch, beyond, c), // (0, 2)
          across(patch, c, left)};  // (-1, 2)
}

/// One round of Loop subdivision of the patch, kept to the stars of the corners of sub-triangle
/// `child` (0, 1, 2: the one at corner a, b, c; 3: the middle one). The new values needed there
/// are those of the three corners and of the edges touching them, whose masks read only the
/// corners' stars.
LocalPatch refine(const LocalPatch& patch, int child) {
  const int old_count = int(patch.weights.rows());
  std::map<std::pair<int, int>, int> edge_vertex;
  const auto mid = [&](int i, int j) {
    const auto key = std::minmax(i, j);
    return edge_vertex.try_emplace(key, old_count + int(edge_vertex.size())).first->second;
  };
  std::vector<LocalTriangle> fine;
  for (const auto& [i, j, k] : patch.triangles) {
    const int ij = mid(i, j), jk = mid(j, k), ki = mid(k, i);
    fine.push_back({i, ij, ki});
    fine.push_back({ij, j, jk});
    fine.push_back({ki, jk, k});
    fine.push_back({ij, jk, ki});
  }
  Eigen::MatrixXd weights =
      Eigen::MatrixXd::Zero(old_count + int(edge_vertex.size()), patch.weights.cols());
  std::vector<char> known(std::size_t(weights.rows()), 0);
  const auto is_corner = [&](int v) {
    return std::find(patch.corners.begin(), patch.corners.end(), v) != patch.corners.end();
  };
  for (const int v : patch.corners) {
    known[std::size_t(v)] = 1;
    const auto sharp_ring = sharp_neighbours(patch, v);
    if (sharp_ring.size() >= 3) { // a corner of sharp edges stays
      weights.row(v) = patch.weights.row(v);
      continue;
    }
    if (sharp_ring.size() == 2) {
      // A boundary or crease is a cubic B-spline curve of its vertices: (b1 + 6 v + b2) / 8.
      const int b1 = sharp_ring[0], b2 = sharp_ring[1];
      weights.row(v) =
          0.75 * patch.weights.row(v) + 0.125 * (patch.weights.row(b1) + patch.weights.row(b2));
      continue;
    }
    const auto ring = neighbours(patch, v);
    const double beta = loop_beta(int(ring.size()));
    weights.row(v) = (1.0 - double(ring.size()) * beta) * patch.weights.row(v);
    for (const int w : ring)
      weights.row(v) += beta * patch.weights.row(w);
  }
  for (const auto& [edge, index] : edge_vertex) {
    const auto [i, j] = edge;
    if (!is_corner(i) && !is_corner(j))
      continue;
    std::vector<int> opposite;
    for (const auto& tri : patch.triangles)
      for (int k = 0; k < 3; ++k)
        if (tri[k] != i && tri[k] != j && std::count(tri.begin(), tri.end(), i) &&
            std::count(tri.begin(), tri.end(), j))
          opposite.push_back(tri[k]);
    TEXSIM_VERIFY(opposite.size() == 1 || opposite.size() == 2,
                  "Loop basis: an edge at a corner has " << opposite.size() << " triangles");
    known[std::size_t(index)] = 1;
    if (sharp(patch, i, j)) { // a boundary or crease edge: its midpoint
      weights.row(index) = 0.5 * (patch.weights.row(i) + patch.weights.row(j));
      continue;
    }
    weights.row(index) = 0.375 * (patch.weights.row(i) + patch.weights.row(j)) +
                         0.125 * (patch.weights.row(opposite[0]) + patch.weights.row(opposite[1]));
  }

  const auto [a, b, c] = patch.corners;
  const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
  const std::array<LocalTriangle, 4> children{
      {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {bc, ca, ab}}};
  const LocalTriangle& corners = children[std::size_t(child)];
  // Keep the fine triangles around the child's corners, vertices renumbered in increasing order.
  std::vector<LocalTriangle> kept;
  for (const auto& tri : fine)
    if (std::any_of(tri.begin(), tri.end(), [&](int v) {
          return std::find(corners.begin(), corners.end(), v) != corners.end();
        }))
      kept.push_back(tri);
  std::vector<int> used;
  for (const auto& tri : kept)
    used.insert(used.end(), tri.begin(), tri.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  const auto renumber = [&](int v) {
    return int(std::lower_bound(used.begin(), used.end(), v) - used.begin());
  };
  LocalPatch result;
  result.weights.resize(Eigen::Index(used.size()), weights.cols());
  for (std::size_t n = 0; n < used.size(); ++n) {
    TEXSIM_VERIFY(known[std::size_t(used[n])], "Loop basis: a refined star needs a value outside "
                                               "the corners' stars");
    result.weights.row(Eigen::Index(n)) = weights.row(used[n]);
  }
  for (const auto& tri : kept)
    result.triangles.push_back({renumber(tri[0]), renumber(tri[1]), renumber(tri[2])});
  result.corners = {renumber(corners[0]), renumber(corners[1]), renumber(corners[2])};
  const auto is_used = [&](int v) { return std::binary_search(used.begin(), used.end(), v); };
  for (const auto& [i, j] : patch.creases) {
    const int m = mid(i, j); // a crease is an edge of the patch's triangles: it was split
    for (const auto& [x, y] : {std::pair{i, m}, std::pair{m, j}})
      if (is_used(x) && is_used(y))
        result.creases.insert(std::minmax(renumber(x), renumber(y)));
  }
  return result;
}

/// Sub-triangle of (s, t) and the point's coordinates in it; `scale` picks up ds'/ds.
int descend(double& s, double& t, double& scale) {
  if (1.0 - s - t > 0.5) {
    s *= 2;
    t *= 2;
    scale *= 2;
    return 0;
  }
  if (s > 0.5) {
    s = 2 * s - 1;
    t *= 2;
    scale *= 2;
    return 1;
  }
  if (t > 0.5) {
    s *= 2;
    t = 2 * t - 1;
    scale *= 2;
    return 2;
  }
  // The middle sub-triangle (bc, ca, ab) is the parent turned by half a turn.
  s = 1 - 2 * s;
  t = 1 - 2 * t;
  scale *= -2;
  return 3;
}

} // namespace

double loop_beta(int valence) {
  const double n = valence;
  const double spread = 3.0 + 2.0 * std::cos(2.0 * std::numbers::pi / n);
  return (5.0 / 8.0 - spread * spread / 64.0) / n;
}

LoopPatchBasis::LoopPatchBasis(const TriangleMesh& mesh, const MeshTopology& topology,
                               std::span<const char> creases)
    : mesh_(mesh), topology_(topology), creases_(creases) {
  TEXSIM_VERIFY(creases_.empty() || creases_.size() == std::size_t(topology.num_edges()),
                "Loop basis: " << creases_.size() << " crease flags for " << topology.num_edges()
                               << " edges");
}

bool LoopPatchBasis::sharp_edge(std::int32_t v, std::int32_t w) const {
  const std::int32_t e = topology_.find_edge(v, w);
  return topology_.edge_triangles(e).size() == 1 || (!creases_.empty() && creases_[std::size_t(e)]);
}

LoopPatchBasis::Fan LoopPatchBasis::fan(std::int32_t v) const {
  // Around a fan every triangle's edge leaving v is the next one's edge entering v: following
  // them from the one edge no triangle enters by (an open fan) or from any edge (a closed one)
  // must visit every triangle once.
  const auto star = topology_.vertex_triangles().row(v);
  if (star.empty())
    return Fan::kBroken;
  std::map<std::int32_t, std::int32_t> entering_from; // previous vertex -> next vertex
  for (const std::int32_t t : star) {
    const auto& tri = mesh_.triangles[t];
    const int k = int(std::find(tri.begin(), tri.end(), v) - tri.begin());
    if (!entering_from.emplace(tri[(k + 2) % 3], tri[(k + 1) % 3]).second)
      return Fan::kBroken;
  }
  std::vector<std::int32_t> starts;
  for (const auto& [previous, next] : entering_from)
    if (std::none_of(entering_from.begin(), entering_from.end(),
                     [&](const auto& other) { return other.second == previous; }))
      starts.push_back(previous);
  if (starts.size() > 1 || (starts.empty() && star.size() < 3))
    return Fan::kBroken;
  std::int32_t w = starts.empty() ? entering_from.begin()->first : starts.front();
  for (std::size_t step = 0; step < star.size(); ++step) {
    const auto next = entering_from.find(w);
    if (next == entering_from.end())
      return Fan::kBroken;
    w = next->second;
  }
  if (starts.empty())
    return w == entering_from.begin()->first ? Fan::kClosed : Fan::kBroken;
  return entering_from.count(w) ? Fan::kBroken : Fan::kOpen;
}

bool LoopPatchBasis::evaluable(std::int32_t t) const {
  const auto& tri = mesh_.triangles[t];
  return std::none_of(tri.begin(), tri.end(),
                      [&](std::int32_t v) { return fan(v) == Fan::kBroken; });
}

bool LoopPatchBasis::is_regular(std::int32_t t) const {
  const auto& tri = mesh_.triangles[t];
  return std::all_of(tri.begin(), tri.end(), [&](std::int32_t v) {
    const auto ring = topology_.vertex_neighbors().row(v);
    return topology_.vertex_triangles().row(v).size() == 6 && fan(v) == Fan::kClosed &&
           std::none_of(ring.begin(), ring.end(), [&](std::int32_t w) { return sharp_edge(v, w); });
  });
}

namespace {

/// Triangle t with its corners' stars, numbered canonically (the controls, in that order): the
/// corners a, b, c as 0, 1, 2, then the vertices met walking each corner's fan counter-clockwise
/// from the triangle's next corner. Triangles whose neighbourhoods have the same structure get the
/// same local patch, so every computation on it gives the same bits.
LocalPatch star_patch(const TriangleMesh& mesh, const MeshTopology& topology,
                      std::span<const char> creases, std::int32_t t,
                      std::vector<std::int32_t>& controls) {
  std::vector<std::int32_t> star;
  for (const std::int32_t corner : mesh.triangles[t]) {
    const auto row = topology.vertex_triangles().row(corner);
    star.insert(star.end(), row.begin(), row.end());
  }
  std::sort(star.begin(), star.end());
  star.erase(std::unique(star.begin(), star.end()), star.end());
  const auto& tri = mesh.triangles[t];
  controls.assign(tri.begin(), tri.end());
  const auto local = [&](std::int32_t v) {
    return int(std::find(controls.begin(), controls.end(), v) - controls.begin());
  };
  // The vertex after w around v, counter-clockwise (offset 1: the star triangle (v, w, x)) or
  // clockwise (offset 2: the star triangle (v, x, w)); -1 past the end of an open fan.
  const auto around_from = [&](std::int32_t v, std::int32_t w, int offset) {
    for (const std::int32_t s : star) {
      const auto& around = mesh.triangles[s];
      for (int k = 0; k < 3; ++k)
        if (around[k] == v && around[(k + offset) % 3] == w)
          return around[(k + 3 - offset) % 3];
    }
    return std::int32_t{-1};
  };
  for (int c = 0; c < 3; ++c) {
    const std::int32_t v = tri[c], first = tri[(c + 1) % 3];
    // Counter-clockwise from the triangle's next corner; an open fan then clockwise from it.
    for (const int offset : {1, 2}) {
      std::int32_t w = first;
      for (std::size_t step = 0; step < star.size(); ++step) {
        w = around_from(v, w, offset);
        if (w < 0 || w == first)
          break;
        if (local(w) == int(controls.size()))
          controls.push_back(w);
      }
      if (w == first)
        break; // a closed fan: walked whole
    }
  }
  LocalPatch patch;
  for (const std::int32_t s : star) {
    const auto& around = mesh.triangles[s];
    LocalTriangle numbered{local(around[0]), local(around[1]), local(around[2])};
    std::rotate(numbered.begin(), std::min_element(numbered.begin(), numbered.end()),
                numbered.end());
    patch.triangles.push_back(numbered);
  }
  std::sort(patch.triangles.begin(), patch.triangles.end());
  TEXSIM_VERIFY(std::all_of(patch.triangles.begin(), patch.triangles.end(),
                            [&](const auto& numbered) {
                              return std::all_of(numbered.begin(), numbered.end(),
                                                 [&](int v) { return v < int(controls.size()); });
                            }),
                "Loop basis: the stars of triangle " << t << "'s corners are not whole fans");
  if (!creases.empty())
    for (const std::int32_t around : star)
      for (const std::int32_t e : topology.triangle_edges(around))
        if (creases[std::size_t(e)]) {
          const auto [v, w] = topology.edges()[std::size_t(e)];
          patch.creases.insert(std::minmax(local(v), local(w)));
        }
  patch.corners = {0, 1, 2};
  patch.weights =
      Eigen::MatrixXd::Identity(Eigen::Index(controls.size()), Eigen::Index(controls.size()));
  return patch;
}

} // namespace

std::vector<std::int32_t> LoopPatchBasis::controls(std::int32_t t) const {
  TEXSIM_VERIFY(evaluable(t),
                "Loop basis: triangle " << t << " has a corner whose triangles are not one fan");
  std::vector<std::int32_t> canonical;
  const LocalPatch patch = star_patch(mesh_, topology_, creases_, t, canonical);
  if (!is_regular_patch(patch))
    return canonical;
  std::vector<std::int32_t> lattice;
  for (const int v : regular_lattice(patch))
    lattice.push_back(canonical[std::size_t(v)]);
  return lattice;
}

std::vector<std::int32_t> LoopPatchBasis::structure(std::int32_t t) const {
  TEXSIM_VERIFY(evaluable(t),
                "Loop basis: triangle " << t << " has a corner whose triangles are not one fan");
  std::vector<std::int32_t> canonical;
  const LocalPatch patch = star_patch(mesh_, topology_, creases_, t, canonical);
  std::vector<std::int32_t> flat;
  for (const auto& numbered : patch.triangles)
    flat.insert(flat.end(), numbered.begin(), numbered.end());
  flat.push_back(-1); // then the creases, which change the functions too
  for (const auto& [v, w] : patch.creases)
    flat.insert(flat.end(), {v, w});
  return flat;
}

void LoopPatchBasis::evaluate(std::int32_t t, double s, double t_param,
                              PatchBasisValues& out) const {
  TEXSIM_VERIFY(evaluable(t),
                "Loop basis: triangle " << t << " has a corner whose triangles are not one fan");
  std::vector<std::int32_t> canonical;
  LocalPatch patch = star_patch(mesh_, topology_, creases_, t, canonical);
  if (is_regular_patch(patch)) {
    const auto basis = regular_patch_basis(s, t_param);
    out.value.assign(basis.value.begin(), basis.value.end());
    out.d_s.assign(basis.d_s.begin(), basis.d_s.end());
    out.d_t.assign(basis.d_t.begin(), basis.d_t.end());
    return;
  }
  double scale = 1.0;
  for (int depth = 1; depth <= kMaxDepth; ++depth) {
    patch = refine(patch, descend(s, t_param, scale));
    if (!is_regular_patch(patch))
      continue;
    const auto lattice = regular_lattice(patch);
    const auto basis = regular_patch_basis(s, t_param);
    Eigen::VectorXd value = Eigen::VectorXd::Zero(patch.weights.cols());
    Eigen::VectorXd d_s = value, d_t = value;
    for (std::size_t k = 0; k < 12; ++k) {
      const auto row = patch.weights.row(lattice[k]).transpose();
      value += basis.value[k] * row;
      d_s += basis.d_s[k] * row;
      d_t += basis.d_t[k] * row;
    }
    out.value.assign(value.begin(), value.end());
    out.d_s.resize(std::size_t(d_s.size()));
    out.d_t.resize(std::size_t(d_t.size()));
    for (Eigen::Index k = 0; k < d_s.size(); ++k) {
      out.d_s[std::size_t(k)] = scale * d_s[k];
      out.d_t[std::size_t(k)] = scale * d_t[k];
    }
    return;
  }
  throw Error("Loop basis: a point of triangle " + std::to_string(t) +
              " lies on an extraordinary corner (no regular sub-triangle within " +
              std::to_string(kMaxDepth) + " subdivisions)");
}

void LoopPatchBasis::limit_value(std::int32_t v, std::span<const double> values, int components,
                                 std::span<double> out) const {
  const Fan kind = fan(v);
  TEXSIM_VERIFY(kind != Fan::kBroken,
                "Loop basis: vertex " << v << "'s triangles are not one fan (no limit point)");
  const auto value = [&](std::int32_t w, int c) {
    return values[std::size_t(w) * std::size_t(components) + std::size_t(c)];
  };
  std::vector<std::int32_t> sharp_ring;
  for (const std::int32_t w : topology_.vertex_neighbors().row(v))
    if (sharp_edge(v, w))
      sharp_ring.push_back(w);
  if (sharp_ring.size() >= 3) { // a corner of sharp edges
    for (int c = 0; c < components; ++c)
      out[std::size_t(c)] = value(v, c);
    return;
  }
  if (sharp_ring.size() == 2) {
    // The limit of the boundary's or crease's cubic B-spline: (b1 + 4 v + b2) / 6.
    for (int c = 0; c < components; ++c)
      out[std::size_t(c)] =
          (value(sharp_ring[0], c) + 4.0 * value(v, c) + value(sharp_ring[1], c)) / 6.0;
    return;
  }
  TEXSIM_VERIFY(kind == Fan::kClosed, "Loop basis: boundary vertex " << v << " has "
                                                                     << sharp_ring.size()
                                                                     << " boundary edges");
  const auto ring = topology_.vertex_neighbors().row(v);
  const double n = double(ring.size());
  const double weight = 1.0 / (n + 3.0 / (8.0 * loop_beta(int(ring.size()))));
  for (int c = 0; c < components; ++c) {
    double sum = 0;
    for (const std::int32_t w : ring)
      sum += values[std::size_t(w) * std::size_t(components) + std::size_t(c)];
    out[std::size_t(c)] =
        (1.0 - n * weight) * values[std::size_t(v) * std::size_t(components) + std::size_t(c)] +
        weight * sum;
  }
}

} // namespace texsim::geom
