// A volume split in z over the ranks, written as .vti pieces under a .pvti, reads back (through
// VTK's parallel reader) as the whole volume, voxel for voxel, with its spacing and origin; ranks
// without planes write no piece.
#include "par/comm.hpp"
#include "support/test_data.hpp"
#include "vol/parallel_vti_writer.hpp"
#include "vol/vti_io.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <variant>

namespace texsim::vol {
namespace {
namespace fs = std::filesystem;

float value(int i, int j, int k, int c) {
  return static_cast<float>(i + 10 * j + 100 * k) + 0.25f * static_cast<float>(c);
}

/// This rank's planes [z_first, z_last] of `nz`: the nz - 1 gaps between planes split over the
/// ranks, lower ranks first, each piece sharing its last plane with the next; nullopt when the
/// rank gets no gap.
std::optional<std::array<int, 2>> share(const par::Comm& comm, int nz) {
  const int gaps = nz - 1;
  const auto start = [&](int rank) { return (gaps * rank + comm.size - 1) / comm.size; };
  const int first = start(comm.rank), last = start(comm.rank + 1);
  if (first == last)
    return std::nullopt;
  return std::array<int, 2>{first, last};
}

TEST(ParallelVti, PiecesReadBackAsTheWholeVolume) {
  const par::Comm comm = par::world();
  for (const int nz : {11, 2}) {
    const std::array<int, 3> whole{5, 4, nz};
    const fs::path dir = test::scratch_dir("parallel_vti_" + std::to_string(nz));
    const auto mine = share(comm, nz);
    std::optional<RgbGrid> colour;
    std::optional<ScalarGrid> density;
    if (mine) {
      const int planes = (*mine)[1] - (*mine)[0] + 1;
      colour.emplace(Dims{5, 4, planes});
      density.emplace(Dims{5, 4, planes});
      colour->set_spacing({0.5, 0.5, 2.0});
      colour->set_origin({1.0, -2.0, 3.0});
      density->set_spacing({0.5, 0.5, 2.0});
      density->set_origin({1.0, -2.0, 3.0});
      for (int k = 0; k < planes; ++k)
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 5; ++i) {
            const int z = (*mine)[0] + k;
            colour->at(i, j, k) = {value(i, j, z, 0), value(i, j, z, 1), value(i, j, z, 2)};
            density->at(i, j, k) = value(i, j, z, 0);
          }
    }
    const int z_first = mine ? (*mine)[0] : 0;
    const auto rgb = write_parallel_vti(comm, dir, "colour", {colour ? &*colour : nullptr, z_first},
                                        whole, "colour");
    const auto scalar = write_parallel_vti(
        comm, dir, "density", {density ? &*density : nullptr, z_first}, whole, "density");
    MPI_Barrier(comm.raw);

    const auto read_rgb = std::get<RgbGrid>(read_vti(rgb));
    const auto read_scalar = std::get<ScalarGrid>(read_vti(scalar));
    ASSERT_EQ(read_rgb.dims(), (Dims{5, 4, nz}));
    ASSERT_EQ(read_scalar.dims(), (Dims{5, 4, nz}));
    EXPECT_EQ(read_rgb.spacing(), (std::array<double, 3>{0.5, 0.5, 2.0}));
    EXPECT_EQ(read_rgb.origin(), (std::array<double, 3>{1.0, -2.0, 3.0}));
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 5; ++i) {
          ASSERT_EQ(read_scalar.at(i, j, k), value(i, j, k, 0)) << i << " " << j << " " << k;
          for (int c = 0; c < 3; ++c)
            ASSERT_EQ(read_rgb.at(i, j, k)[c], value(i, j, k, c)) << i << " " << j << " " << k;
        }
    int pieces = 0;
    for (const auto& entry : fs::directory_iterator(dir / "colour"))
      pieces += entry.path().extension() == ".vti";
    EXPECT_EQ(pieces, std::min(comm.size, nz - 1));
  }
}

} // namespace
} // namespace texsim::vol
