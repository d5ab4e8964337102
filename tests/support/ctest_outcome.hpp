#pragma once
/// How a GoogleTest program tells ctest what it did: passed, skipped (a test called GTEST_SKIP,
/// e.g. for absent real data) or failed. tests/CMakeLists.txt registers every program with
/// SKIP_RETURN_CODE TEXSIM_TEST_SKIPPED_EXIT_CODE, so a skip is counted as one, never as a pass.

namespace texsim::test {

/// Ordered so that the worst outcome of several ranks is their maximum.
enum class Outcome { kPassed = 0, kSkipped = 1, kFailed = 2 };

/// The outcome of this process's RUN_ALL_TESTS(), which returned `gtest_result`. A run that
/// matched no test at all fails: its filter is stale (e.g. cmake must be re-run).
Outcome outcome_of_run(int gtest_result);

/// The exit code ctest reads for `outcome`.
int exit_code_of(Outcome outcome);

} // namespace texsim::test
