// GoogleTest entry point shared by every test program: MPI and PETSc are initialised once, and only
// rank 0 prints gtest's report, so a failure on another rank still fails the program (exit code)
// without interleaving output. Every rank exits with the worst outcome of all ranks, so ctest sees
// one verdict: failed, skipped (see ctest_outcome.hpp) or passed. TEXSIM_TEST_ALL_RANKS=1 (mpirun
// -x) lets every rank print, to see a failure that happens on another rank only.
#include "ctest_outcome.hpp"
#include "par/petsc_session.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdlib>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  texsim::par::PetscSession session(argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0 && !std::getenv("TEXSIM_TEST_ALL_RANKS")) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int result = RUN_ALL_TESTS();
  const int local = static_cast<int>(texsim::test::outcome_of_run(result));
  int worst = local;
  MPI_Allreduce(&local, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return texsim::test::exit_code_of(static_cast<texsim::test::Outcome>(worst));
}
