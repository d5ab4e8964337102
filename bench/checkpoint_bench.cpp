// Checkpoint throughput: write (collective MPI-IO + checksums + rename) and verified read of one
// dataset of --mb megabytes split across ranks, against a bare MPI_File_write_at_all of the same
// bytes to the same directory (what the file system gives without HDF5 or verification).
// Prints one JSON object with medians over --repeats runs.
// Sample run: mpirun -n 2 build/release/bench/checkpoint_bench --mb 256 --repeats 5 --dir /tmp/b
#include "bench_timing.hpp"
#include "core/log.hpp"
#include "io/checkpoint_store.hpp"
#include "par/petsc_session.hpp"

#include <mpi.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace {
using texsim::par::Comm;

using texsim::bench::median;
using texsim::bench::timed;
} // namespace

int main(int argc, char** argv) {
  texsim::par::PetscSession session(argc, argv);
  const Comm comm = texsim::par::world();
  texsim::log::init(comm.rank, /*quiet=*/true); // stdout holds the JSON only
  double megabytes = 256;
  int repeats = 5;
  std::filesystem::path dir = "/tmp/texsim_checkpoint_bench";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--mb")
      megabytes = std::stod(argv[i + 1]);
    else if (flag == "--repeats")
      repeats = std::stoi(argv[i + 1]);
    else if (flag == "--dir")
      dir = argv[i + 1];
  }
  const std::uint64_t global = static_cast<std::uint64_t>(megabytes * 1e6 / sizeof(double));
  const std::uint64_t first = global * comm.rank / comm.size;
  const std::uint64_t last = global * (comm.rank + 1) / comm.size;
  std::vector<double> data(last - first), back(last - first);
  for (std::uint64_t i = first; i < last; ++i)
    data[i - first] = 1e-3 * static_cast<double>(i % 100003);

  if (comm.is_root())
    std::filesystem::remove_all(dir);
  MPI_Barrier(comm.raw);
  texsim::io::CheckpointStore store(comm, dir / "checkpoints", "bench", 2);
  std::vector<double> write_s, read_s, raw_s;
  for (int r = 0; r < repeats; ++r) {
    write_s.push_back(timed(comm, [&] {
      auto writer = store.begin(r);
      writer.write<double>("u", data, first, global);
      writer.commit();
    }));
    read_s.push_back(timed(comm, [&] {
      auto reader = store.open(store.path_of(r));
      reader.read<double>("u", back, first, last - first);
    }));
    raw_s.push_back(timed(comm, [&] {
      const auto path = (dir / "raw.bin").string();
      MPI_File file;
      MPI_File_open(comm.raw, path.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY, MPI_INFO_NULL,
                    &file);
      MPI_File_write_at_all(file, first * sizeof(double), data.data(),
                            static_cast<int>(data.size()), MPI_DOUBLE, MPI_STATUS_IGNORE);
      MPI_File_sync(file);
      MPI_File_close(&file);
    }));
  }
  const bool exact = std::equal(data.begin(), data.end(), back.begin());
  int all_exact = 0, local_exact = exact;
  MPI_Allreduce(&local_exact, &all_exact, 1, MPI_INT, MPI_MIN, comm.raw);
  if (comm.is_root()) {
    const double bytes = global * sizeof(double);
    nlohmann::json result = {{"ranks", comm.size},
                             {"megabytes", bytes / 1e6},
                             {"repeats", repeats},
                             {"write_s", median(write_s)},
                             {"read_verify_s", median(read_s)},
                             {"raw_mpiio_write_s", median(raw_s)},
                             {"write_MBps", bytes / 1e6 / median(write_s)},
                             {"read_verify_MBps", bytes / 1e6 / median(read_s)},
                             {"raw_mpiio_write_MBps", bytes / 1e6 / median(raw_s)},
                             {"write_over_raw", median(write_s) / median(raw_s)},
                             {"round_trip_exact", all_exact == 1}};
    std::cout << result.dump() << std::endl;
  }
  MPI_Barrier(comm.raw);
  if (comm.is_root())
    std::filesystem::remove_all(dir);
  return 0;
}
