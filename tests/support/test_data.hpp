#pragma once
/// Paths the tests share: the source tree, the built binary, real data under data/, and per-test
/// scratch directories.
#include <filesystem>
#include <string>
#include <vector>

namespace texsim::test {

/// The repository root (where config/ and data/ live).
std::filesystem::path source_dir();

/// The texsim executable built alongside the tests.
std::filesystem::path texsim_binary();

/// Suffix of the test suites that use real data: tests/CMakeLists.txt runs them as a ctest of their
/// own (<program>_real_data_n<ranks>), which ctest reports as Skipped when data/ is absent while
/// the program's other tests still count as passed.
inline constexpr const char* real_data_suite_suffix = "OnRealData";

/// data/<relative> if scripts/fetch-data has put it there, otherwise an empty path; tests call
/// GTEST_SKIP() with the message from missing_data_message() when it is empty. Only tests in a
/// suite named *OnRealData may call it (the test fails otherwise).
std::filesystem::path real_data(const std::string& relative);
std::string missing_data_message(const std::string& relative);

/// A fresh empty directory for this test, the same path on every rank. Collective.
std::filesystem::path scratch_dir(const std::string& name);

/// Files under `dir` (recursively) named as temporaries of core/atomic_output.hpp
/// (`<name>.tmp-<pid>`): what an interrupted or failed write leaves behind. Not collective.
std::vector<std::filesystem::path> temporary_files_under(const std::filesystem::path& dir);

} // namespace texsim::test
