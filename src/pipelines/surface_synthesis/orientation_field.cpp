#include "pipelines/surface_synthesis/orientation_field.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"
#include "par/fetch_from_owners.hpp"

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
                                          int level, std::int64_t first) {
  TEXSIM_VERIFY(level >= 0, "mesh level " << level << " is negative");
  const CounterRng rng(seed, kOrientationStream);
  std::vector<geom::Vec3> directions(normals.size());
  const auto count = static_cast<std::int64_t>(normals.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t v = 0; v < count; ++v) {
    const double angle =
        2.0 * std::numbers::pi * rng.uniform(std::uint64_t(first + v), std::uint32_t(level));
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

CoarserOrientation coarser_orientation(std::span<const ParentFace> parents,
                                       std::span<const geom::Vec3> coarse_directions,
                                       std::span<const geom::Vec3> coarse_normals) {
  verify_sizes(coarse_normals.size(), coarse_directions.size(), "coarser normals");
  CoarserOrientation coarser{parents, {}, {}};
  coarser.directions.resize(parents.size());
  coarser.normals.resize(parents.size());
  const auto coarse_count = std::int64_t(coarse_directions.size());
  for (std::size_t v = 0; v < parents.size(); ++v) {
    if (!parents[v].found())
      continue;
    for (int corner = 0; corner < 3; ++corner) {
      const std::int32_t u = parents[v].vertices[std::size_t(corner)];
      TEXSIM_VERIFY(u >= 0 && u < coarse_count,
                    "parent vertex " << u << " of vertex " << v << " is not a vertex of the "
                                     << coarse_count << " of the coarser level");
      coarser.directions[v][std::size_t(corner)] = coarse_directions[std::size_t(u)];
      coarser.normals[v][std::size_t(corner)] = coarse_normals[std::size_t(u)];
    }
  }
  return coarser;
}

OwnersFrames fetch_frames(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                          std::span<const std::int64_t> ids, std::span<const geom::Vec3> directions,
                          std::span<const geom::Vec3> normals) {
  verify_sizes(normals.size(), directions.size(), "normals of the run");
  // A vertex's direction and normal travel together.
  using Frame = std::array<double, 6>;
  std::vector<Frame> mine;
  mine.reserve(directions.size());
  for (std::size_t u = 0; u < directions.size(); ++u) {
    const geom::Vec3& s = directions[u];
    const geom::Vec3& n = normals[u];
    mine.push_back({s.x(), s.y(), s.z(), n.x(), n.y(), n.z()});
  }
  const auto fetched =
      par::fetch_from_owners(comm, rank_offsets, ids, std::span<const Frame>(mine));
  OwnersFrames frames;
  for (const Frame& f : fetched) {
    frames.directions.emplace_back(f[0], f[1], f[2]);
    frames.normals.emplace_back(f[3], f[4], f[5]);
  }
  return frames;
}

CoarserOrientation coarser_orientation(const par::Comm& comm, std::span<const ParentFace> parents,
                                       std::span<const std::int64_t> coarse_offsets,
                                       std::span<const geom::Vec3> coarse_directions,
                                       std::span<const geom::Vec3> coarse_normals) {
  std::vector<std::int64_t> corners;
  for (const auto& parent : parents)
    if (parent.found())
      corners.insert(corners.end(), parent.vertices.begin(), parent.vertices.end());
  const auto fetched =
      fetch_frames(comm, coarse_offsets, corners, coarse_directions, coarse_normals);
  CoarserOrientation coarser{parents, {}, {}};
  coarser.directions.resize(parents.size());
  coarser.normals.resize(parents.size());
  std::size_t next = 0;
  for (std::size_t v = 0; v < parents.size(); ++v) {
    if (!parents[v].found())
      continue;
    for (std::size_t corner = 0; corner < 3; ++corner, ++next) {
      coarser.directions[v][corner] = fetched.directions[next];
      coarser.normals[v][corner] = fetched.normals[next];
    }
  }
  return coarser;
}

std::vector<geom::Vec3> inherited_directions(std::span<const geom::Vec3> normals,
                                             const CoarserOrientation& coarser, int symmetry,
                                             std::span<const geom::Vec3> random_fallback) {
  TEXSIM_VERIFY(symmetry >= 1, "orientation symmetry " << symmetry << " is below 1");
  verify_sizes(coarser.parents.size(), normals.size(), "parent faces");
  verify_sizes(coarser.directions.size(), normals.size(), "parent corner directions");
  verify_sizes(coarser.normals.size(), normals.size(), "parent corner normals");
  verify_sizes(random_fallback.size(), normals.size(), "fallback directions");
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
    for (std::size_t corner = 0; corner < 3; ++corner) {
      const auto carried = transport(coarser.directions[v][corner], coarser.normals[v][corner], n);
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

} // namespace texsim::pipelines::surface_synthesis
