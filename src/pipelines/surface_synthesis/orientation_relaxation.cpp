#include "pipelines/surface_synthesis/orientation_relaxation.hpp"

#include "core/error.hpp"
#include "par/allgather_runs.hpp"
#include "par/greedy_colouring.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"
#include "par/reproducible_sum.hpp"
#include "pipelines/surface_synthesis/level_part.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Classes of the greedy colouring of the 1-ring graph in vertex id order (par::greedy_colouring
/// on each rank's run, whose rings are `rings`): each class's members in this rank's run, in id
/// order. Every rank has the same number of classes (some may be empty on a rank).
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
  return owned;
}

/// For each vertex of the rank's run, the other ranks that read its direction: the owners of its
/// 1-ring (a ring is symmetric, so they are the ranks whose runs have it in a ring). CSR over the
/// run.
struct DirectionReaders {
  std::vector<std::int64_t> offsets;
  std::vector<std::int32_t> ranks;

  DirectionReaders(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                   const geom::CsrAdjacency& rings) {
    offsets.push_back(0);
    std::vector<std::int32_t> row;
    for (std::int32_t local = 0; local < rings.rows(); ++local) {
      row.clear();
      for (const std::int32_t q : rings.row(local))
        if (const int owner = par::owner_of(rank_offsets, q); owner != comm.rank)
          row.push_back(owner);
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      ranks.insert(ranks.end(), row.begin(), row.end());
      offsets.push_back(std::int64_t(ranks.size()));
    }
  }
};

struct DirectionUpdate {
  std::int64_t vertex;
  double s[3];
};

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
    if (coarser_ != nullptr && coarser_->parents[std::size_t(p - first_)].found())
      for (const std::int32_t u : coarser_->parents[std::size_t(p - first_)].vertices)
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

/// Total energy: the shares of every rank's run summed by par::reproducible_sum, so the value
/// does not depend on the rank count.
double total_energy(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                    const VertexEnergy& energy) {
  const std::int64_t begin = rank_offsets[comm.rank];
  const std::int64_t end = rank_offsets[comm.rank + 1];
  std::vector<double> shares(std::size_t(end - begin));
#pragma omp parallel
  {
    std::vector<double> buffer;
#pragma omp for schedule(static)
    for (std::int64_t p = begin; p < end; ++p)
      shares[std::size_t(p - begin)] = energy.share(std::int32_t(p), buffer);
  }
  return par::reproducible_sum(comm, shares);
}

/// Updates the members of one colour class in this rank's run (`members`, ascending), then sends
/// each new direction to the ranks whose runs have the vertex in a 1-ring.
void relax_class(const par::Comm& comm, std::int64_t first, std::span<const std::int32_t> members,
                 const DirectionReaders& readers, const VertexEnergy& energy,
                 std::vector<geom::Vec3>& directions) {
  std::vector<geom::Vec3> updated(members.size());
  const auto count = std::ptrdiff_t(members.size());
#pragma omp parallel
  {
    std::vector<double> buffer;
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i)
      updated[std::size_t(i)] = energy.relaxed(members[std::size_t(i)], buffer);
  }
  std::vector<std::vector<DirectionUpdate>> outgoing(std::size_t(comm.size));
  for (std::size_t i = 0; i < members.size(); ++i) {
    const std::int32_t p = members[i];
    const geom::Vec3& s = updated[i];
    directions[std::size_t(p)] = s;
    const auto local = std::size_t(p - first);
    for (auto k = readers.offsets[local]; k < readers.offsets[local + 1]; ++k)
      outgoing[std::size_t(readers.ranks[std::size_t(k)])].push_back({p, {s.x(), s.y(), s.z()}});
  }
  for (const auto& update : par::exchange_records(comm, outgoing))
    directions[std::size_t(update.vertex)] = geom::Vec3(update.s[0], update.s[1], update.s[2]);
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
  const std::int64_t first = rank_offsets[std::size_t(comm.rank)];
  const std::int64_t run = rank_offsets[std::size_t(comm.rank) + 1] - first;
  TEXSIM_VERIFY(std::int64_t(coarser->parents.size()) == run,
                coarser->parents.size() << " parent faces for a run of " << run << " vertices");
  const auto coarse_count = std::int64_t(coarser->directions.size());
  TEXSIM_VERIFY(std::int64_t(coarser->normals.size()) == coarse_count,
                coarser->normals.size()
                    << " coarser normals for " << coarse_count << " coarser directions");
  for (std::int64_t i = 0; i < run; ++i)
    for (const std::int32_t u : coarser->parents[std::size_t(i)].vertices)
      TEXSIM_VERIFY(!coarser->parents[std::size_t(i)].found() || (u >= 0 && u < coarse_count),
                    "parent vertex " << u << " of vertex " << first + i << " is not one of the "
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
  const DirectionReaders readers(comm, rank_offsets, rings);
  const VertexEnergy energy(rings, first, normals, coarser, symmetry, directions);
  RelaxationReport report;
  report.colour_classes = std::int32_t(classes.size());
  report.energy.push_back(total_energy(comm, rank_offsets, energy));
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (const auto& members : classes)
      relax_class(comm, first, members, readers, energy, directions);
    report.energy.push_back(total_energy(comm, rank_offsets, energy));
  }
  // The sweeps kept only the 1-ring halos current; every rank gets every run's result.
  static_assert(sizeof(geom::Vec3) == 3 * sizeof(double));
  par::allgather_runs(comm, rank_offsets, directions.data(), 3, MPI_DOUBLE);
  return report;
}

} // namespace texsim::pipelines::surface_synthesis
