// GoogleTest entry point of the test programs that are not MPI programs themselves (tests/app/
// starts texsim as a user would): a skipped test makes ctest report the program as skipped.
#include "ctest_outcome.hpp"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
  return texsim::test::exit_code_of(texsim::test::outcome_of_run(result));
}
