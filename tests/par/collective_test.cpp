#include "par/collective.hpp"

#include "core/error.hpp"

#include <gtest/gtest.h>

namespace texsim::par {
namespace {

TEST(RunCollectively, SuccessOnEveryRankReturnsNormally) {
  const Comm comm = world();
  int calls = 0;
  run_collectively(comm, [&] { ++calls; });
  EXPECT_EQ(calls, 1);
}

TEST(RunCollectively, InputErrorOnLastRankReachesEveryRankWithItsMessage) {
  const Comm comm = world();
  try {
    run_collectively(comm, [&] {
      if (comm.rank == comm.size - 1)
        throw InputError("mesh.off: line 3: expected 3 numbers");
    });
    FAIL() << "no exception on rank " << comm.rank;
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "mesh.off: line 3: expected 3 numbers");
    EXPECT_TRUE(e.on_all_ranks());
  }
}

TEST(RunCollectively, InputErrorOutranksInternalErrorAndLowestRankSpeaks) {
  const Comm comm = world();
  try {
    run_collectively(comm, [&] {
      if (comm.rank == 0)
        throw Error("internal");
      throw InputError("input on rank " + std::to_string(comm.rank));
    });
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), comm.size == 1 ? "never" : "input on rank 1");
  } catch (const Error& e) {
    EXPECT_EQ(comm.size, 1);
    EXPECT_STREQ(e.what(), "internal");
  }
}

} // namespace
} // namespace texsim::par
