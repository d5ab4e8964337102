#include "pipelines/surface_synthesis/orientation_field.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"
#include "par/allgather_runs.hpp"

#include <cmath>
#include <complex>
#include <numbers>

namespace texsim::pipelines::surface_synthesis {
namespace {

constexpr double kParallelToNormal = 1e-9; // relative projected length of a degenerate field vector
constexpr double kCancelledSum = 1e-9;     // |sum of e^{i n theta}| below which inheritance fails

void verify_sizes(std::size_t found, std::size_t expected, const char* what) {
  TEXSIM_VERIFY(found == expected, what << " has " << found << " entries, expected " << expected);
}

} // namespace

std::array<geom::Vec3, 2> tangent_basis(const geom::Vec3& n) {
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) < std::abs(n[axis]))
      axis = i;
  const geom::Vec3 e1 = n.cross(geom::Vec3::Unit(axis)).normalized();
  return {e1, n.cross(e1)};
}

std::optional<geom::Vec3> transport(const geom::Vec3& v, const geom::Vec3& from,
                                    const geom::Vec3& to) {
  // Rodrigues' formula for the rotation about k = from x to with cos = from.to, sin = |k|:
  // R v = c v + k x v + (k.v) k / (1 + c).
  const double c = from.dot(to);
  if (1.0 + c < kOppositeNormals)
    return std::nullopt;
  const geom::Vec3 k = from.cross(to);
  return c * v + k.cross(v) + (k.dot(v) / (1.0 + c)) * k;
}

double signed_angle(const geom::Vec3& from, const geom::Vec3& to, const geom::Vec3& n) {
  return std::atan2(n.dot(from.cross(to)), from.dot(to) - from.dot(n) * to.dot(n));
}

std::optional<double> relative_angle(const geom::Vec3& s_p, const geom::Vec3& n_p,
                                     const geom::Vec3& s_q, const geom::Vec3& n_q) {
  const auto carried = transport(s_q, n_q, n_p);
  if (!carried)
    return std::nullopt;
  return signed_angle(s_p, *carried, n_p);
}

double symmetric_residue(double angle, int symmetry) {
  const double period = 2.0 * std::numbers::pi / symmetry;
  return angle - period * std::floor(angle / period + 0.5);
}

geom::Vec3 direction_at_angle(const geom::Vec3& n, double angle) {
  const auto [e1, e2] = tangent_basis(n);
  return std::cos(angle) * e1 + std::sin(angle) * e2;
}

std::vector<geom::Vec3> random_directions(std::span<const geom::Vec3> normals, std::uint64_t seed,
                                          int level) {
  TEXSIM_VERIFY(level >= 0, "mesh level " << level << " is negative");
  const CounterRng rng(seed, kOrientationStream);
  std::vector<geom::Vec3> directions(normals.size());
  const auto count = static_cast<std::int64_t>(normals.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t v = 0; v < count; ++v) {
    const double angle =
        2.0 * std::numbers::pi * rng.uniform(std::uint64_t(v), std::uint32_t(level));
    directions[v] = direction_at_angle(normals[v], angle);
  }
  return directions;
}

std::vector<geom::Vec3> projected_directions(std::span<const geom::Vec3> normals,
                                             std::span<const geom::Vec3> field,
                                             std::int64_t* degenerate_count) {
  verify_sizes(field.size(), normals.size(), "orientation field");
  std::vector<geom::Vec3> directions(normals.size());
  std::int64_t degenerate = 0;
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const geom::Vec3& f = field[v];
    if (!f.allFinite())
      TEXSIM_INPUT_ERROR("orientation field at vertex " << v << " is (" << f.x() << ", " << f.y()
                                                        << ", " << f.z()
                                                        << "): expected finite components");
    const geom::Vec3& n = normals[v];
    const geom::Vec3 in_plane = f - f.dot(n) * n;
    const double length = in_plane.norm();
    if (length > kParallelToNormal * f.norm() && length > 0.0) {
      directions[v] = in_plane / length;
    } else {
      directions[v] = tangent_basis(n)[0];
      ++degenerate;
    }
  }
  if (degenerate_count != nullptr)
    *degenerate_count = degenerate;
  return directions;
}

std::vector<geom::Vec3> inherited_directions(std::span<const geom::Vec3> normals,
                                             const CoarserOrientation& coarser, int symmetry,
                                             std::span<const geom::Vec3> random_fallback) {
  TEXSIM_VERIFY(symmetry >= 1, "orientation symmetry " << symmetry << " is below 1");
  verify_sizes(coarser.parents.size(), normals.size(), "parent faces");
  verify_sizes(random_fallback.size(), normals.size(), "fallback directions");
  verify_sizes(coarser.normals.size(), coarser.directions.size(), "coarser normals");
  const auto coarse_count = static_cast<std::int32_t>(coarser.directions.size());
  for (std::size_t v = 0; v < normals.size(); ++v)
    for (const std::int32_t u : coarser.parents[v].vertices)
      TEXSIM_VERIFY(!coarser.parents[v].found() || (u >= 0 && u < coarse_count),
                    "parent vertex " << u << " of vertex " << v << " is not a vertex of the "
                                     << coarse_count << " of the coarser level");
  std::vector<geom::Vec3> directions(normals.size());
  const auto count = static_cast<std::int64_t>(normals.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t v = 0; v < count; ++v) {
    const ParentFace& parent = coarser.parents[v];
    directions[v] = random_fallback[v];
    if (!parent.found())
      continue;
    const geom::Vec3& n = normals[v];
    const auto [e1, e2] = tangent_basis(n);
    std::complex<double> sum = 0.0;
    for (int corner = 0; corner < 3; ++corner) {
      const std::int32_t u = parent.vertices[corner];
      const auto carried = transport(coarser.directions[u], coarser.normals[u], n);
      if (!carried)
        continue;
      const double theta = std::atan2(carried->dot(e2), carried->dot(e1));
      sum += parent.weights[corner] * std::polar(1.0, symmetry * theta);
    }
    if (std::abs(sum) > kCancelledSum) {
      const double theta = std::arg(sum) / symmetry;
      directions[v] = std::cos(theta) * e1 + std::sin(theta) * e2;
    }
  }
  return directions;
}

std::vector<geom::Vec3> inherited_directions(const par::Comm& comm,
                                             std::span<const std::int64_t> rank_offsets,
                                             std::span<const geom::Vec3> normals,
                                             const CoarserOrientation& coarser, int symmetry,
                                             std::span<const geom::Vec3> random_fallback) {
  verify_sizes(random_fallback.size(), normals.size(), "fallback directions");
  TEXSIM_VERIFY(rank_offsets.size() == std::size_t(comm.size) + 1 &&
                    rank_offsets.back() == std::int64_t(normals.size()),
                "inherited_directions: rank offsets do not split the " << normals.size()
                                                                       << " vertices");
  const auto first = std::size_t(rank_offsets[std::size_t(comm.rank)]);
  const auto run = std::size_t(rank_offsets[std::size_t(comm.rank) + 1]) - first;
  const auto mine = inherited_directions(normals.subspan(first, run), coarser, symmetry,
                                         random_fallback.subspan(first, run));
  std::vector<geom::Vec3> directions(normals.size());
  std::copy(mine.begin(), mine.end(), directions.begin() + std::ptrdiff_t(first));
  static_assert(sizeof(geom::Vec3) == 3 * sizeof(double));
  par::allgather_runs(comm, rank_offsets, directions.data(), 3, MPI_DOUBLE);
  return directions;
}

} // namespace texsim::pipelines::surface_synthesis
