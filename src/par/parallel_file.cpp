#include "par/parallel_file.hpp"

#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "par/collective.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <climits>
#include <string>
#include <system_error>

namespace texsim::par {
namespace {

/// The most bytes one MPI call moves: well inside int, whatever the datatype.
constexpr std::uint64_t kMaxCallBytes = std::uint64_t(1) << 30;

std::string mpi_error_text(int code) {
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  return std::string(text, static_cast<std::size_t>(length));
}

/// `runs` cut into groups of at most kMaxCallBytes, a longer run split across groups.
std::vector<std::vector<ByteRun>> in_call_sized_groups(std::span<const ByteRun> runs) {
  std::vector<std::vector<ByteRun>> groups(1);
  std::uint64_t in_group = 0;
  for (ByteRun run : runs) {
    while (!run.bytes.empty()) {
      if (in_group == kMaxCallBytes) {
        groups.emplace_back();
        in_group = 0;
      }
      const std::size_t take = static_cast<std::size_t>(
          std::min<std::uint64_t>(run.bytes.size(), kMaxCallBytes - in_group));
      groups.back().push_back({run.offset, run.bytes.first(take)});
      in_group += take;
      run.offset += take;
      run.bytes = run.bytes.subspan(take);
    }
  }
  if (groups.back().empty())
    groups.pop_back();
  return groups;
}

} // namespace

std::filesystem::path shared_temporary_path(const Comm& comm, const std::filesystem::path& path) {
  long id = static_cast<long>(::getpid());
  MPI_Bcast(&id, 1, MPI_LONG, 0, comm.raw);
  return temporary_path_of(path, id);
}

ParallelFile::ParallelFile(const Comm& comm, std::filesystem::path path)
    : comm_(comm), path_(std::move(path)), temporary_(shared_temporary_path(comm, path_)) {
  const int opened = MPI_File_open(comm_.raw, temporary_.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY,
                                   MPI_INFO_NULL, &file_);
  // A temporary left by an earlier process of the same id must not keep its tail.
  const int emptied = opened == MPI_SUCCESS ? MPI_File_set_size(file_, 0) : opened;
  run_collectively(comm_, [&] {
    TEXSIM_VERIFY(emptied == MPI_SUCCESS,
                  path_.string() << ": cannot create the file (" << mpi_error_text(emptied) << ")");
  });
}

ParallelFile::~ParallelFile() {
  if (file_ != MPI_FILE_NULL)
    close();
  if (!committed_ && comm_.is_root()) {
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void ParallelFile::close() {
  MPI_File_close(&file_);
  file_ = MPI_FILE_NULL;
}

void ParallelFile::write_at(std::uint64_t offset, std::span<const std::byte> bytes) {
  for (const auto& group : in_call_sized_groups(std::array{ByteRun{offset, bytes}})) {
    const ByteRun& run = group.front();
    MPI_Status status;
    const int written =
        MPI_File_write_at(file_, static_cast<MPI_Offset>(run.offset), run.bytes.data(),
                          static_cast<int>(run.bytes.size()), MPI_BYTE, &status);
    TEXSIM_VERIFY(written == MPI_SUCCESS, path_.string() << ": cannot write " << run.bytes.size()
                                                         << " bytes at " << run.offset << " ("
                                                         << mpi_error_text(written) << ")");
  }
}

void ParallelFile::write_runs(std::span<const ByteRun> runs) {
  TEXSIM_VERIFY(
      std::is_sorted(runs.begin(), runs.end(),
                     [](const ByteRun& a, const ByteRun& b) { return a.offset < b.offset; }),
      path_.string() << ": runs not sorted by offset");
  const auto groups = in_call_sized_groups(runs);
  int calls = static_cast<int>(groups.size());
  MPI_Allreduce(MPI_IN_PLACE, &calls, 1, MPI_INT, MPI_MAX, comm_.raw);
  int failure = MPI_SUCCESS;
  const auto note = [&](int code) {
    if (failure == MPI_SUCCESS)
      failure = code;
  };
  for (int call = 0; call < calls; ++call) {
    if (std::size_t(call) >= groups.size()) { // nothing left here: the others still write
      note(MPI_File_set_view(file_, 0, MPI_BYTE, MPI_BYTE, "native", MPI_INFO_NULL));
      MPI_Status status;
      note(MPI_File_write_all(file_, nullptr, 0, MPI_BYTE, &status));
      continue;
    }
    // The group's runs as one file type (where they go) and one memory type (where they are).
    const auto& group = groups[std::size_t(call)];
    std::vector<int> lengths;
    std::vector<MPI_Aint> in_file, in_memory;
    for (const ByteRun& run : group) {
      lengths.push_back(static_cast<int>(run.bytes.size()));
      in_file.push_back(static_cast<MPI_Aint>(run.offset));
      MPI_Aint address = 0;
      MPI_Get_address(run.bytes.data(), &address);
      in_memory.push_back(address);
    }
    MPI_Datatype file_type = MPI_DATATYPE_NULL, memory_type = MPI_DATATYPE_NULL;
    const int count = static_cast<int>(group.size());
    MPI_Type_create_hindexed(count, lengths.data(), in_file.data(), MPI_BYTE, &file_type);
    MPI_Type_create_hindexed(count, lengths.data(), in_memory.data(), MPI_BYTE, &memory_type);
    MPI_Type_commit(&file_type);
    MPI_Type_commit(&memory_type);
    note(MPI_File_set_view(file_, 0, MPI_BYTE, file_type, "native", MPI_INFO_NULL));
    MPI_Status status;
    note(MPI_File_write_all(file_, MPI_BOTTOM, 1, memory_type, &status));
    MPI_Type_free(&file_type);
    MPI_Type_free(&memory_type);
  }
  note(MPI_File_set_view(file_, 0, MPI_BYTE, MPI_BYTE, "native", MPI_INFO_NULL));
  run_collectively(comm_, [&] {
    TEXSIM_VERIFY(failure == MPI_SUCCESS,
                  path_.string() << ": cannot write (" << mpi_error_text(failure) << ")");
  });
}

void ParallelFile::commit() {
  const int synced = MPI_File_sync(file_);
  close();
  run_collectively(comm_, [&] {
    TEXSIM_VERIFY(synced == MPI_SUCCESS,
                  path_.string() << ": cannot flush the file (" << mpi_error_text(synced) << ")");
    if (comm_.is_root()) {
      commit_temporary(temporary_, path_);
      committed_ = true;
    }
  });
}

} // namespace texsim::par
