#include "pipelines/surface_synthesis/orientation_relaxation.hpp"

#include "core/error.hpp"
#include "par/greedy_colouring.hpp"
#include "par/id_runs.hpp"
#include "par/record_exchange.hpp"
#include "par/reproducible_sum.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace texsim::pipelines::surface_synthesis {
namespace {

/// Classes of the greedy colouring of the 1-ring graph in vertex id order (par::greedy_colouring
/// on each rank's run, whose rings are `rings`): each class's members in this rank's run, in id
/// order, as offsets in the run. Every rank has the same number of classes (some may be empty on a
/// rank).
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
    owned[std::size_t(colouring.owned_class[std::size_t(v - first)])].push_back(
        std::int32_t(v - first));
  return owned;
}

/// The rank's run and the other ranks' vertices in its 1-rings (the halo), numbered locally: the
/// run's vertex first + i is i, the halo follows in id order. Each run vertex also lists the other
/// ranks that read its direction: the owners of its 1-ring (a ring is symmetric, so they are the
/// ranks whose runs have it in a ring).
struct RingHalo {
  std::int64_t first = 0;
  std::int32_t run = 0;
  std::vector<std::int64_t> halo; ///< ascending global ids
  geom::CsrAdjacency rings;       ///< per run vertex, local ids
  std::vector<std::int64_t> reader_offsets;
  std::vector<std::int32_t> readers;

  RingHalo(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
           const geom::CsrAdjacency& global_rings)
      : first(rank_offsets[std::size_t(comm.rank)]), run(global_rings.rows()) {
    for (const std::int32_t q : global_rings.indices)
      if (q < first || q >= first + run)
        halo.push_back(q);
    std::sort(halo.begin(), halo.end());
    halo.erase(std::unique(halo.begin(), halo.end()), halo.end());
    rings.offsets = global_rings.offsets;
    for (const std::int32_t q : global_rings.indices)
      rings.indices.push_back(local(q));
    reader_offsets.push_back(0);
    std::vector<std::int32_t> row;
    for (std::int32_t i = 0; i < run; ++i) {
      row.clear();
      for (const std::int32_t q : global_rings.row(i))
        if (const int owner = par::owner_of(rank_offsets, q); owner != comm.rank)
          row.push_back(owner);
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      readers.insert(readers.end(), row.begin(), row.end());
      reader_offsets.push_back(std::int64_t(readers.size()));
    }
  }

  /// The local id of a run or halo vertex.
  std::int32_t local(std::int64_t v) const {
    if (v >= first && v < first + run)
      return std::int32_t(v - first);
    return run + std::int32_t(std::lower_bound(halo.begin(), halo.end(), v) - halo.begin());
  }
};

struct DirectionUpdate {
  std::int64_t vertex;
  double s[3];
};

/// Sends the directions of the run's vertices `locals` to the ranks that read them and stores the
/// directions other ranks sent in the halo of `directions` (run, then halo). Collective.
void send_to_readers(const par::Comm& comm, const RingHalo& halo,
                     std::span<const std::int32_t> locals, std::vector<geom::Vec3>& directions) {
  std::vector<std::vector<DirectionUpdate>> outgoing(std::size_t(comm.size));
  for (const std::int32_t i : locals) {
    const geom::Vec3& s = directions[std::size_t(i)];
    for (auto k = halo.reader_offsets[std::size_t(i)]; k < halo.reader_offsets[std::size_t(i) + 1];
         ++k)
      outgoing[std::size_t(halo.readers[std::size_t(k)])].push_back(
          {halo.first + i, {s.x(), s.y(), s.z()}});
  }
  for (const auto& update : par::exchange_records(comm, std::move(outgoing)))
    directions[std::size_t(halo.local(update.vertex))] =
        geom::Vec3(update.s[0], update.s[1], update.s[2]);
}

/// What one vertex's update reads: its 1-ring's directions and normals (run and halo, local ids)
/// and its parent face's corners on the fixed coarser level.
class VertexEnergy {
public:
  /// `normals` and `directions`: the run's, then the halo's.
  VertexEnergy(const RingHalo& halo, const std::vector<geom::Vec3>& normals,
               const CoarserOrientation* coarser, int symmetry,
               const std::vector<geom::Vec3>& directions)
      : halo_(halo), normals_(normals),
        coarser_(coarser != nullptr && !coarser->parents.empty() ? coarser : nullptr),
        symmetry_(symmetry), directions_(directions) {}

  /// phi_qp of run vertex p's 1-ring into `angles`, then those of its parent-face vertices;
  /// returns the number of 1-ring angles.
  std::size_t angles(std::int32_t p, std::vector<double>& angles) const {
    angles.clear();
    const geom::Vec3& s_p = directions_[std::size_t(p)];
    const geom::Vec3& n_p = normals_[std::size_t(p)];
    for (const std::int32_t q : halo_.rings.row(p))
      if (const auto phi =
              relative_angle(s_p, n_p, directions_[std::size_t(q)], normals_[std::size_t(q)]))
        angles.push_back(*phi);
    const std::size_t ring_count = angles.size();
    if (coarser_ != nullptr && coarser_->parents[std::size_t(p)].found())
      for (std::size_t corner = 0; corner < 3; ++corner)
        if (const auto phi = relative_angle(s_p, n_p, coarser_->directions[std::size_t(p)][corner],
                                            coarser_->normals[std::size_t(p)][corner]))
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
    const geom::Vec3& s_p = directions_[std::size_t(p)];
    const double theta = symmetric_residue(minimising_rotation(buffer, symmetry_), symmetry_);
    if (!(rotation_energy(buffer, symmetry_, theta) < rotation_energy(buffer, symmetry_, 0.0)))
      return s_p;
    const geom::Vec3& n_p = normals_[std::size_t(p)];
    const geom::Vec3 rotated = std::cos(theta) * s_p + std::sin(theta) * n_p.cross(s_p);
    return (rotated - rotated.dot(n_p) * n_p).normalized();
  }

private:
  const RingHalo& halo_;
  const std::vector<geom::Vec3>& normals_; ///< run, then halo
  const CoarserOrientation* coarser_;
  int symmetry_;
  const std::vector<geom::Vec3>& directions_; ///< run, then halo
};

/// Total energy: the shares of the run's vertices summed by par::reproducible_sum, so the value
/// does not depend on the rank count.
double total_energy(const par::Comm& comm, std::int32_t run, const VertexEnergy& energy) {
  std::vector<double> shares(std::size_t(run), 0.0);
#pragma omp parallel
  {
    std::vector<double> buffer;
#pragma omp for schedule(static)
    for (std::int32_t p = 0; p < run; ++p)
      shares[std::size_t(p)] = energy.share(p, buffer);
  }
  return par::reproducible_sum(comm, shares);
}

/// Updates the run's members of one colour class (local ids), then sends their new directions to
/// the ranks that read them.
void relax_class(const par::Comm& comm, const RingHalo& halo, std::span<const std::int32_t> members,
                 const VertexEnergy& energy, std::vector<geom::Vec3>& directions) {
  std::vector<geom::Vec3> updated(members.size());
  const auto count = std::ptrdiff_t(members.size());
#pragma omp parallel
  {
    std::vector<double> buffer;
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i)
      updated[std::size_t(i)] = energy.relaxed(members[std::size_t(i)], buffer);
  }
  for (std::size_t i = 0; i < members.size(); ++i)
    directions[std::size_t(members[i])] = updated[i];
  send_to_readers(comm, halo, members, directions);
}

void verify_inputs(const par::Comm& comm, std::span<const std::int64_t> rank_offsets,
                   const geom::CsrAdjacency& rings, std::span<const geom::Vec3> normals,
                   const CoarserOrientation* coarser, int symmetry, int sweeps,
                   const std::vector<geom::Vec3>& directions) {
  TEXSIM_VERIFY(symmetry >= 1, "orientation symmetry " << symmetry << " is below 1");
  TEXSIM_VERIFY(sweeps >= 0, "relaxation sweeps " << sweeps << " is negative");
  TEXSIM_VERIFY(std::int64_t(rank_offsets.size()) == comm.size + 1 && rank_offsets.front() == 0 &&
                    std::is_sorted(rank_offsets.begin(), rank_offsets.end()),
                "rank offsets must be " << comm.size + 1 << " non-decreasing values from 0");
  const std::int64_t run =
      rank_offsets[std::size_t(comm.rank) + 1] - rank_offsets[std::size_t(comm.rank)];
  TEXSIM_VERIFY(std::int64_t(directions.size()) == run && std::int64_t(normals.size()) == run &&
                    std::int64_t(rings.rows()) == run,
                directions.size() << " directions, " << normals.size() << " normals and "
                                  << rings.rows() << " rings for a run of " << run << " vertices");
  if (coarser == nullptr || coarser->parents.empty())
    return;
  TEXSIM_VERIFY(std::int64_t(coarser->parents.size()) == run &&
                    std::int64_t(coarser->directions.size()) == run &&
                    std::int64_t(coarser->normals.size()) == run,
                coarser->parents.size()
                    << " parent faces, " << coarser->directions.size() << " and "
                    << coarser->normals.size() << " corner directions and normals for a run of "
                    << run << " vertices");
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
                                  const geom::CsrAdjacency& rings,
                                  std::span<const geom::Vec3> normals,
                                  const CoarserOrientation* coarser, int symmetry, int sweeps,
                                  std::vector<geom::Vec3>& directions) {
  verify_inputs(comm, rank_offsets, rings, normals, coarser, symmetry, sweeps, directions);
  const auto classes = colour_classes(comm, rank_offsets, rings);
  const RingHalo halo(comm, rank_offsets, rings);
  // The run's directions and normals, then the halo's, fetched from their owners.
  auto fetched = fetch_frames(comm, rank_offsets, halo.halo, directions, normals);
  std::vector<geom::Vec3> ghosted(directions);
  ghosted.insert(ghosted.end(), fetched.directions.begin(), fetched.directions.end());
  std::vector<geom::Vec3> ghosted_normals(normals.begin(), normals.end());
  ghosted_normals.insert(ghosted_normals.end(), fetched.normals.begin(), fetched.normals.end());
  const VertexEnergy energy(halo, ghosted_normals, coarser, symmetry, ghosted);
  RelaxationReport report;
  report.colour_classes = std::int32_t(classes.size());
  report.energy.push_back(total_energy(comm, halo.run, energy));
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (const auto& members : classes)
      relax_class(comm, halo, members, energy, ghosted);
    report.energy.push_back(total_energy(comm, halo.run, energy));
  }
  std::copy(ghosted.begin(), ghosted.begin() + halo.run, directions.begin());
  return report;
}

} // namespace texsim::pipelines::surface_synthesis
