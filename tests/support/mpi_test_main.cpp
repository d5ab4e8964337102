// GoogleTest entry point shared by every test program: MPI and PETSc are initialised once, and only
// rank 0 prints gtest's report, so a failure on another rank still fails the program (exit code)
// without interleaving output.
#include "par/petsc_session.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  texsim::par::PetscSession session(argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
