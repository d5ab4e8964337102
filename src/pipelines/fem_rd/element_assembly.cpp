#include "pipelines/fem_rd/element_assembly.hpp"

#include "core/error.hpp"
#include "par/petsc_session.hpp"

#include <algorithm>

namespace texsim::pipelines::fem_rd {

ElementAssembly::ElementAssembly(std::int32_t owned_begin, std::int32_t owned_end,
                                 const std::vector<std::int64_t>& offsets,
                                 const std::vector<std::int32_t>& functions)
    : owned_begin_(owned_begin), owned_end_(owned_end) {
  const std::size_t elements = offsets.size() - 1;
  const auto owned = [&](std::int32_t row) { return row >= owned_begin && row < owned_end; };
  // The pattern: every (row, column) pair of an element with an owned row, sorted and unique.
  std::vector<std::uint64_t> pairs;
  for (std::int32_t row = owned_begin; row < owned_end; ++row) // a diagonal even without elements
    pairs.push_back(std::uint64_t(row - owned_begin) << 32 | std::uint32_t(row));
  entry_offsets_.assign(1, 0);
  for (std::size_t e = 0; e < elements; ++e) {
    const auto first = functions.begin() + offsets[e], last = functions.begin() + offsets[e + 1];
    for (auto i = first; i != last; ++i)
      if (owned(*i))
        for (auto j = first; j != last; ++j)
          pairs.push_back(std::uint64_t(*i - owned_begin) << 32 | std::uint32_t(*j));
    const std::int64_t k = offsets[e + 1] - offsets[e];
    entry_offsets_.push_back(entry_offsets_.back() + k * k);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  row_offsets_.assign(std::size_t(owned_end - owned_begin) + 1, 0);
  columns_.reserve(pairs.size());
  for (const std::uint64_t pair : pairs) {
    ++row_offsets_[(pair >> 32) + 1];
    columns_.push_back(PetscInt(pair & 0xffffffffu));
  }
  for (std::size_t r = 0; r + 1 < row_offsets_.size(); ++r)
    row_offsets_[r + 1] += row_offsets_[r];
  pairs = {};

  // Each entry's slot among the values, then each value's entries in increasing order (a
  // counting sort over the entries).
  const auto slot = [&](std::int32_t row, std::int32_t column) -> std::int64_t {
    if (!owned(row))
      return -1;
    const auto first = columns_.begin() + row_offsets_[std::size_t(row - owned_begin)];
    const auto last = columns_.begin() + row_offsets_[std::size_t(row - owned_begin) + 1];
    return std::lower_bound(first, last, column) - columns_.begin();
  };
  std::vector<std::int64_t> slots(std::size_t(entry_offsets_.back()), -1);
  for (std::size_t e = 0; e < elements; ++e) {
    const auto k = offsets[e + 1] - offsets[e];
    for (std::int64_t i = 0; i < k; ++i)
      for (std::int64_t j = 0; j < k; ++j)
        slots[std::size_t(entry_offsets_[e] + i * k + j)] =
            slot(functions[std::size_t(offsets[e] + i)], functions[std::size_t(offsets[e] + j)]);
  }
  // Entry indices are read once per value every assembly: 32 bits halve that traffic.
  TEXSIM_VERIFY(entry_offsets_.back() <= std::int64_t(UINT32_MAX),
                "element assembly: " << entry_offsets_.back() << " entries on one rank (at most "
                                     << UINT32_MAX << "); use more ranks");
  source_offsets_.assign(columns_.size() + 1, 0);
  for (const std::int64_t s : slots)
    if (s >= 0)
      ++source_offsets_[std::size_t(s) + 1];
  for (std::size_t v = 0; v < columns_.size(); ++v)
    source_offsets_[v + 1] += source_offsets_[v];
  sources_.resize(std::size_t(source_offsets_.back()));
  std::vector<std::int64_t> next(source_offsets_.begin(), source_offsets_.end() - 1);
  for (std::size_t entry = 0; entry < slots.size(); ++entry)
    if (slots[entry] >= 0)
      sources_[std::size_t(next[std::size_t(slots[entry])]++)] = std::uint32_t(entry);
}

std::vector<double> ElementAssembly::sum_entries(std::span<const double> entries) const {
  TEXSIM_VERIFY(std::int64_t(entries.size()) == entry_count(),
                "sum_entries: " << entries.size() << " entries for " << entry_count());
  std::vector<double> values(columns_.size());
#pragma omp parallel for schedule(static)
  for (std::size_t v = 0; v < values.size(); ++v) {
    double sum = 0.0;
    for (auto k = source_offsets_[v]; k < source_offsets_[v + 1]; ++k)
      sum += entries[sources_[std::size_t(k)]];
    values[v] = sum;
  }
  return values;
}

par::PetscMat ElementAssembly::create_matrix(const par::Comm& comm) const {
  par::PetscMat matrix;
  const std::vector<double> zeros(columns_.size(), 0.0);
  const PetscInt rows = owned_end_ - owned_begin_;
  TEXSIM_PETSC_CALL(MatCreateMPIAIJWithArrays(comm.raw, rows, rows, PETSC_DETERMINE,
                                              PETSC_DETERMINE, row_offsets_.data(), columns_.data(),
                                              zeros.data(), matrix.address()));
  TEXSIM_PETSC_CALL(MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE));
  return matrix;
}

void ElementAssembly::set_values(Mat matrix, const std::vector<double>& values) const {
  TEXSIM_VERIFY(values.size() == columns_.size(),
                "set_values: " << values.size() << " values for " << columns_.size() << " slots");
  const PetscInt rows = owned_end_ - owned_begin_;
  TEXSIM_PETSC_CALL(MatUpdateMPIAIJWithArrays(matrix, rows, rows, PETSC_DETERMINE, PETSC_DETERMINE,
                                              row_offsets_.data(), columns_.data(), values.data()));
}

} // namespace texsim::pipelines::fem_rd
