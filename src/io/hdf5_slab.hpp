#pragma once
/// Reading part of an HDF5 dataset: a run of indices along its first (slowest) axis, e.g. some
/// z-planes of a [nz, ny, nx, C] grid, so that each rank can read its own share of a large
/// dataset straight into its destination instead of one rank reading it whole.
#include "io/hdf5_scalar_type.hpp"
#include "io/scalar_type.hpp"

#include <hdf5.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace texsim::io {

/// The dataset's extent along each axis, slowest first. `where` names it in errors.
std::vector<hsize_t> dataset_shape(hid_t dataset, const std::string& where);

/// Indices [begin, end) of `dataset`'s first axis (all of the other axes), converted to `type`,
/// into `out`, which must hold exactly those elements (a mismatch throws). Chunk checksums are
/// verified as HDF5 reads. Not collective.
void read_leading_slab(hid_t dataset, std::uint64_t begin, std::uint64_t end, ScalarType type,
                       void* out, std::size_t out_count, const std::string& where);

template <class T>
void read_leading_slab(hid_t dataset, std::uint64_t begin, std::uint64_t end, std::span<T> out,
                       const std::string& where) {
  read_leading_slab(dataset, begin, end, scalar_type_of<T>(), out.data(), out.size(), where);
}

} // namespace texsim::io
