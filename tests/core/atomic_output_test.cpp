// Atomic output: a file appears under its final name only complete, a writer that fails half-way
// leaves the previous file as it was, and no temporary file is ever left behind.
#include "core/atomic_output.hpp"
#include "core/error.hpp"
#include "support/test_data.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace texsim {
namespace {
namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Names of the entries of `dir`, sorted.
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// Runs `work`, expects texsim::Error whose message contains `needle`.
template <class Work> void expect_error_naming(Work&& work, const std::string& needle) {
  try {
    work();
    ADD_FAILURE() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(AtomicOutput, TemporaryNamesAreNameDotTmpDashPidInTheSameDirectory) {
  EXPECT_EQ(temporary_path_of("out/frames/a.vtu", 1234), fs::path("out/frames/a.vtu.tmp-1234"));
  EXPECT_EQ(temporary_path_of("a.vtu"), fs::path("a.vtu.tmp-" + std::to_string(::getpid())));
  EXPECT_EQ(final_name_of_temporary("a.vtu.tmp-1234"), "a.vtu");
  EXPECT_EQ(final_name_of_temporary("step_000000020.h5.tmp-7"), "step_000000020.h5");
  for (const char* other : {"a.vtu", "a.vtu.tmp-", "a.vtu.tmp-12x", ".tmp-12", "a.vtu.tmp"})
    EXPECT_FALSE(final_name_of_temporary(other)) << other;
}

TEST(AtomicOutput, WritesContentsAndLeavesNoTemporary) {
  const auto dir = test::scratch_dir("atomic_contents");
  write_atomically(dir / "summary.json", "{\"a\": 1}\n");
  EXPECT_EQ(read_text(dir / "summary.json"), "{\"a\": 1}\n");
  write_atomically(dir / "summary.json", std::string(100000, 'x'));
  EXPECT_EQ(read_text(dir / "summary.json"), std::string(100000, 'x'));
  EXPECT_EQ(entries(dir), std::vector<std::string>{"summary.json"});
}

TEST(AtomicOutput, PathWriterRunsOnTheTemporaryAndIsCommittedOverTheFinalName) {
  const auto dir = test::scratch_dir("atomic_path_writer");
  const auto path = dir / "grid.vdb";
  write_atomically(path, "old");
  fs::path seen;
  write_atomically(path, [&](const fs::path& temporary) {
    seen = temporary;
    EXPECT_FALSE(fs::exists(temporary));
    std::ofstream(temporary) << "new";
    // While the writer runs, readers of the final name still see the previous file.
    EXPECT_EQ(read_text(path), "old");
  });
  EXPECT_EQ(seen, temporary_path_of(path));
  EXPECT_EQ(read_text(path), "new");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"grid.vdb"});
}

TEST(AtomicOutput, AWriterThrowingMidwayLeavesThePreviousFileAndNoTemporary) {
  const auto dir = test::scratch_dir("atomic_writer_throws");
  const auto path = dir / "frame_0.vtu";
  write_atomically(path, "complete previous frame");
  struct DiskFull : std::runtime_error {
    using std::runtime_error::runtime_error;
  };
  EXPECT_THROW(write_atomically(path,
                                [&](const fs::path& temporary) {
                                  std::ofstream(temporary) << "half a fr";
                                  throw DiskFull("no space left on device");
                                }),
               DiskFull);
  EXPECT_EQ(read_text(path), "complete previous frame");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"frame_0.vtu"});
}

TEST(AtomicOutput, PartsAreWrittenInOrderAndAProducerThrowingMidwayKeepsThePreviousFile) {
  const auto dir = test::scratch_dir("atomic_parts");
  const auto path = dir / "textured.obj";
  write_atomically_in_parts(path, [](const TextSink& emit) {
    emit("v 0 0 0\n");
    emit(std::string(300000, 'x'));
    emit("");
    emit("\nf 1 1 1\n");
  });
  EXPECT_EQ(read_text(path), "v 0 0 0\n" + std::string(300000, 'x') + "\nf 1 1 1\n");
  EXPECT_THROW(write_atomically_in_parts(path,
                                         [](const TextSink& emit) {
                                           emit("v 1 1 1\n");
                                           throw std::runtime_error("out of memory");
                                         }),
               std::runtime_error);
  EXPECT_EQ(read_text(path), "v 0 0 0\n" + std::string(300000, 'x') + "\nf 1 1 1\n");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"textured.obj"});
}

TEST(AtomicOutput, AWriterThatWritesNothingIsAnErrorNamingTheFile) {
  const auto dir = test::scratch_dir("atomic_writer_silent");
  const auto path = dir / "slices.png";
  expect_error_naming([&] { write_atomically(path, [](const fs::path&) {}); }, path.string());
  EXPECT_TRUE(entries(dir).empty());
}

TEST(AtomicOutput, AMissingDirectoryIsAnErrorNamingTheFile) {
  const auto path = test::scratch_dir("atomic_missing_dir") / "no_such_dir" / "summary.json";
  expect_error_naming([&] { write_atomically(path, "text"); }, path.string());
}

TEST(AtomicOutput, AFailedRenameRemovesTheTemporaryAndKeepsWhatWasThere) {
  const auto dir = test::scratch_dir("atomic_rename_fails");
  // A non-empty directory at the final name: rename(2) cannot replace it.
  const auto path = dir / "frames";
  fs::create_directories(path / "kept");
  expect_error_naming([&] { write_atomically(path, "text"); }, path.string());
  EXPECT_EQ(entries(dir), std::vector<std::string>{"frames"});
  EXPECT_TRUE(fs::is_directory(path / "kept"));
}

TEST(AtomicOutput, CommitTemporaryMovesACompleteFileIntoPlace) {
  const auto dir = test::scratch_dir("atomic_commit");
  const auto path = dir / "step_000000010.h5";
  const auto temporary = temporary_path_of(path, 42);
  std::ofstream(temporary) << "checkpoint";
  commit_temporary(temporary, path);
  EXPECT_EQ(read_text(path), "checkpoint");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"step_000000010.h5"});
  expect_error_naming([&] { commit_temporary(temporary, dir / "other.h5"); },
                      (dir / "other.h5").string());
}

} // namespace
} // namespace texsim
