#include "pipelines/surface_synthesis/orientation_relaxation.hpp"

#include "core/error.hpp"
#include "par/greedy_colouring.hpp"
#include "par/record_exchange.hpp"
#include "pipelines/surface_synthesis/level_part.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Classes of the greedy colouring of the 1-ring graph in vertex id order (par::greedy_colouring
/// on each rank's run, whose rings are `rings`), each class with every rank's members in id order.
std::vector<std::vector<std::int32_t>> colour_classes(const par::Comm& comm,
                                                      std::span<const std::int64_t> rank_offsets,
                                                      const geom::CsrAdjacency& rings) {
  const std::int64_t first = rank_offsets[std::size_t(comm.rank)];
  const std::int64_t end = rank_offsets[std::size_t(comm.rank) + 1];
  par::OwnedAdjacency rows;
  rows.neighbours.assign(rings.indices.begin(), rings.indices.end());
  rows.offsets.assign(rings.offsets.begin(), rings.offsets.end());
  const auto colouring = par::greedy_colouring(comm, rank_offsets, std::move(rows),
                                               [](std::int64_t) { return std::uint64_t(0); });
  std::vector<std::vector<std::int32_t>> owned(std::size_t(colouring.classes));
  for (std::int64_t v = first; v < end; ++v)
    owned[std::size_t(colouring.owned_class[std::size_t(v - first)])].push_back(std::int32_t(v));
  std::vector<std::vector<std::int32_t>> classes;
  for (const auto& members : owned)
    classes.push_back(par::allgather_records(comm, members));
  return classes;
}

/// What one vertex's update reads: the level's geometry and directions and the fixed coarser level.
class VertexEnergy {
public:
  /// `rings`: the 1-rings of the rank's run, which starts at vertex `first`.
  VertexEnergy(const geom::CsrAdjacency& rings, std::int64_t first,
               std::span<const geom::Vec3> normals, const CoarserOrientation* coarser, int symmetry,
               const std::vector<geom::Vec3>& directions)
      : rings_(rings), first_(first), normals_(normals),
        coarser_(coarser != nullptr && !coarser->parents.empty() ? coarser : nullptr),
        symmetry_(symmetry), directions_(directions) {}

  /// phi_qp of p's 1-ring into `angles`, then those of its parent-face vertices; returns the
  /// number of 1-ring angles.
  std::size_t angles(std::int32_t p, std::vector<double>& angles) const {
    angles.clear();
    const geom::Vec3& s_p = directions_[p];
    const geom::Vec3& n_p = normals_[p];
    for (const std::int32_t q : rings_.row(std::int32_t(p - first_)))
      if (const auto phi = relative_angle(s_p, n_p, directions_[q], normals_[q]))
        angles.push_back(*phi);
    const std::size_t ring_count = angles.size();
    if (coarser_ != nullptr && coarser_->parents[p].found())
      for (const std::int32_t u : coarser_->parents[p].vertices)
        if (const auto phi =
                relative_angle(s_p, n_p, coarser_->directions[u], coarser_->normals[u]))
          angles.push_back(*phi);
    return ring_count;
  }

  /// p's share of the total energy: half its 1-ring terms (each edge is seen from both ends) and
  /// all its parent-face terms.
  double share(std::int32_t p, std::vector<double>& buffer) const {
    const std::size_t ring_count = angles(p, buffer);
    const std::span<const double> all(buffer);
    return 0.5 * rotation_energy(all.first(ring_count), symmetry_, 0.0) +
           rotation_energy(all.subspan(ring_count), symmetry_, 0.0);
  }

  /// s_p rotated about n_p by the exact minimiser of E_p, or s_p itself when that does not lower
  /// E_p strictly.
  geom::Vec3 relaxed(std::int32_t p, std::vector<double>& buffer) const {
    angles(p, buffer);
    const geom::Vec3& s_p = directions_[p];
    const double theta = symmetric_residue(minimising_rotation(buffer, symmetry_), symmetry_);
    if (!(rotation_energy(buffer, symmetry_, theta) < rotation_energy(buffer, symmetry_, 0.0)))
      return s_p;
    const geom::Vec3& n_p = normals_[p];
    const geom::Vec3 rotated = std::cos(theta) * s_p + std::sin(theta) * n_p.cross(s_p);
    return (rotated - rotated.dot(n_p) * n_p).normalized();
  }

private:
  const geom::CsrAdjacency& rings_;
  std::int64_t first_;
  std::span<const geom::Vec3> normals_;
  const CoarserOrientation* coarser_;
  int symmetry_;
  const std::vector<geom::Vec3>& directions_;
};

/// Total energy: each rank sums the shares of its run, the shares are all-gathered and added in
/// vertex id order, so the value does not depend on the rank count.
double total_energy(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                    const VertexEnergy& energy) {
  const std::int64_t begin = rank_offsets[comm.rank];
  const std::int64_t end = rank_offsets[comm.rank + 1];
  std::vector<double> shares(rank_offsets.back());
#pragma omp parallel
  {
    std::vector<double> buffer;
#pragma omp for schedule(static)
    for (std::int64_t p = begin; p < end; ++p)
      shares[p] = energy.share(std::int32_t(p), buffer);
  }
  std::vector<int> counts(comm.size), displacements(comm.size);
  for (int r = 0; r < comm.size; ++r) {
    counts[r] = int(rank_offsets[r + 1] - rank_offsets[r]);
    displacements[r] = int(rank_offsets[r]);
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DOUBLE, shares.data(), counts.data(), displacements.data(),
                 MPI_DOUBLE, comm.raw);
  double total = 0.0;
  for (const double share : shares)
    total += share;
  return total;
}

/// Updates the members of one colour class in this rank's run, then all-gathers the class's new
/// directions (runs are ascending, so the gathered members come in the class's id order).
void relax_class(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                 std::span<const std::int32_t> members, const VertexEnergy& energy,
                 std::vector<geom::Vec3>& directions) {
  std::vector<int> counts(comm.size), displacements(comm.size);
  std::vector<std::ptrdiff_t> first(comm.size + 1);
  for (int r = 0; r <= comm.size; ++r)
    first[r] = std::lower_bound(members.begin(), members.end(), rank_offsets[r]) - members.begin();
  for (int r = 0; r < comm.size; ++r) {
    counts[r] = int(3 * (first[r + 1] - first[r]));
    displacements[r] = int(3 * first[r]);
  }
  std::vector<double> updated(3 * members.size());
  const std::ptrdiff_t begin = first[comm.rank];
  const std::ptrdiff_t end = first[comm.rank + 1];
#pragma omp parallel
  {
    std::vector<double> buffer;
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = begin; i < end; ++i) {
      const geom::Vec3 s = energy.relaxed(members[i], buffer);
      std::copy(s.data(), s.data() + 3, updated.begin() + 3 * i);
    }
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DOUBLE, updated.data(), counts.data(), displacements.data(),
                 MPI_DOUBLE, comm.raw);
  for (std::size_t i = 0; i < members.size(); ++i)
    directions[members[i]] = geom::Vec3(updated[3 * i], updated[3 * i + 1], updated[3 * i + 2]);
}

void verify_inputs(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                   const geom::TriangleMesh& mesh, std::span<const geom::Vec3> normals,
                   const CoarserOrientation* coarser, int symmetry, int sweeps,
                   const std::vector<geom::Vec3>& directions) {
  const std::int64_t count = mesh.num_vertices();
  TEXSIM_VERIFY(symmetry >= 1, "orientation symmetry " << symmetry << " is below 1");
  TEXSIM_VERIFY(sweeps >= 0, "relaxation sweeps " << sweeps << " is negative");
  TEXSIM_VERIFY(std::int64_t(normals.size()) == count && std::int64_t(directions.size()) == count,
                normals.size() << " normals and " << directions.size() << " directions for "
                               << count << " vertices");
  TEXSIM_VERIFY(
      std::int64_t(rank_offsets.size()) == comm.size + 1 && rank_offsets.front() == 0 &&
          rank_offsets.back() == count && std::is_sorted(rank_offsets.begin(), rank_offsets.end()),
      "rank offsets must be " << comm.size + 1 << " non-decreasing values from 0 to " << count);
  if (coarser == nullptr || coarser->parents.empty())
    return;
  TEXSIM_VERIFY(std::int64_t(coarser->parents.size()) == count,
                coarser->parents.size() << " parent faces for " << count << " vertices");
  const auto coarse_count = std::int64_t(coarser->directions.size());
  TEXSIM_VERIFY(std::int64_t(coarser->normals.size()) == coarse_count,
                coarser->normals.size()
                    << " coarser normals for " << coarse_count << " coarser directions");
  for (std::int64_t p = 0; p < count; ++p)
    for (const std::int32_t u : coarser->parents[p].vertices)
      TEXSIM_VERIFY(!coarser->parents[p].found() || (u >= 0 && u < coarse_count),
                    "parent vertex " << u << " of vertex " << p << " is not one of the "
                                     << coarse_count << " vertices of the coarser level");
}

} // namespace

double rotation_energy(std::span<const double> angles, int symmetry, double theta) {
  double energy = 0.0;
  for (const double phi : angles) {
    const double d = symmetric_residue(phi - theta, symmetry);
    energy += d * d;
  }
  return energy;
}

double minimising_rotation(std::span<const double> angles, int symmetry) {
  if (angles.empty())
    return 0.0;
  const double period = 2.0 * std::numbers::pi / symmetry;
  std::vector<double> sorted(angles.size());
  std::transform(angles.begin(), angles.end(), sorted.begin(), [period](double phi) {
    const double reduced = phi - period * std::floor(phi / period);
    return reduced < period ? reduced : 0.0;
  });
  std::sort(sorted.begin(), sorted.end());
  double sum = 0.0;
  for (const double a : sorted)
    sum += a;
  // Cut k moves the k smallest angles up by one period, so that arrangement's mean is
  // (sum + k period) / m; on the interval where it is the nearest arrangement to theta, E_p is that
  // arrangement's sum of squares, minimised at its mean.
  const auto m = double(sorted.size());
  double best = 0.0;
  double best_energy = 0.0;
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    double candidate = (sum + double(k) * period) / m;
    candidate -= period * std::floor(candidate / period);
    const double energy = rotation_energy(angles, symmetry, candidate);
    if (k == 0 || energy < best_energy) {
      best = candidate;
      best_energy = energy;
    }
  }
  return best < period ? best : 0.0;
}

RelaxationReport relax_directions(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                                  const geom::TriangleMesh& mesh,
                                  std::span<const geom::Vec3> normals,
                                  const CoarserOrientation* coarser, int symmetry, int sweeps,
                                  std::vector<geom::Vec3>& directions) {
  verify_inputs(comm, rank_offsets, mesh, normals, coarser, symmetry, sweeps, directions);
  const std::int64_t first = rank_offsets[std::size_t(comm.rank)];
  const geom::CsrAdjacency rings =
      run_rings(mesh, first, rank_offsets[std::size_t(comm.rank) + 1] - first);
  const auto classes = colour_classes(comm, rank_offsets, rings);
  const VertexEnergy energy(rings, first, normals, coarser, symmetry, directions);
  RelaxationReport report;
  report.colour_classes = std::int32_t(classes.size());
  report.energy.push_back(total_energy(comm, rank_offsets, energy));
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (const auto& members : classes)
      relax_class(comm, rank_offsets, members, energy, directions);
    report.energy.push_back(total_energy(comm, rank_offsets, energy));
  }
  return report;
}

} // namespace texsim::pipelines::surface_synthesis
