#include "ctest_outcome.hpp"

#include <gtest/gtest.h>

#include <iostream>

namespace texsim::test {

Outcome outcome_of_run(int gtest_result) {
  const auto& unit = *::testing::UnitTest::GetInstance();
  if (gtest_result != 0 || unit.failed_test_count() > 0)
    return Outcome::kFailed;
  if (unit.test_to_run_count() == 0) {
    std::cerr << "no test matched the filter: re-run cmake if tests were renamed or removed\n";
    return Outcome::kFailed;
  }
  return unit.skipped_test_count() > 0 ? Outcome::kSkipped : Outcome::kPassed;
}

int exit_code_of(Outcome outcome) {
  switch (outcome) {
  case Outcome::kPassed:
    return 0;
  case Outcome::kSkipped:
    return TEXSIM_TEST_SKIPPED_EXIT_CODE;
  case Outcome::kFailed:
    break;
  }
  return 1;
}

} // namespace texsim::test
