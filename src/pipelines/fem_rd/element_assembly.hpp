#pragma once
/// The sparsity pattern of this rank's rows and the summation of element matrices into them, for
/// any finite element whose functions are vertices (P1 hats, Loop's box splines).
///
/// Each element lists its functions by global vertex id; its K x K entries (row-major) couple
/// them. A value sums its elements' entries in increasing element order, as one thread adding
/// element after element would, so the values are the same bytes for any number of threads, and
/// an element's entries for rows this rank does not own are dropped (each rank computes its rows
/// whole, with no off-process entries). Matrices are MATMPIAIJ with one shared pattern, updated
/// in place.
#include "par/comm.hpp"
#include "par/petsc_handle.hpp"

#include <petscmat.h>

#include <cstdint>
#include <span>
#include <vector>

namespace texsim::pipelines::fem_rd {

class ElementAssembly {
public:
  /// Element e's functions are functions[offsets[e] .. offsets[e + 1]) (global ids); this rank
  /// owns the rows [owned_begin, owned_end).
  ElementAssembly(std::int32_t owned_begin, std::int32_t owned_end,
                  const std::vector<std::int64_t>& offsets,
                  const std::vector<std::int32_t>& functions);

  /// Where element e's K x K entries start in an entry array, and the array's size.
  std::int64_t entry_offset(std::size_t e) const { return entry_offsets_[e]; }
  std::int64_t entry_count() const { return entry_offsets_.back(); }

  /// Pattern-ordered values from every element's entries.
  std::vector<double> sum_entries(std::span<const double> entries) const;

  /// A MATMPIAIJ matrix with this pattern and zero values. Collective.
  par::PetscMat create_matrix(const par::Comm& comm) const;
  /// Copies pattern-ordered values into `matrix` (made by create_matrix). Collective.
  void set_values(Mat matrix, const std::vector<double>& values) const;
  /// Number of stored values of this rank's rows.
  std::size_t value_count() const { return columns_.size(); }

private:
  std::int32_t owned_begin_ = 0, owned_end_ = 0;
  std::vector<PetscInt> row_offsets_; ///< local row -> first entry
  std::vector<PetscInt> columns_;     ///< global column ids, sorted within each row
  std::vector<std::int64_t> entry_offsets_;
  /// For each value: the entries that add into it, increasing (entries [source_offsets_[v],
  /// source_offsets_[v + 1]) of sources_).
  std::vector<std::int64_t> source_offsets_;
  std::vector<std::uint32_t> sources_; ///< entry indices (a rank's entries fit 32 bits: checked)
};

} // namespace texsim::pipelines::fem_rd
