#include "test_data.hpp"

#include "core/atomic_output.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

namespace texsim::test {

std::filesystem::path source_dir() {
  return TEXSIM_SOURCE_DIR;
}

std::filesystem::path texsim_binary() {
  return TEXSIM_BINARY_PATH;
}

std::filesystem::path real_data(const std::string& relative) {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string suite = test ? test->test_suite_name() : "";
  if (!suite.ends_with(real_data_suite_suffix))
    ADD_FAILURE() << "data/" << relative << " is read by suite '" << suite
                  << "': tests on real data belong in a suite named *" << real_data_suite_suffix
                  << ", which ctest reports as skipped when data/ is absent";
  const auto path = source_dir() / "data" / relative;
  return std::filesystem::exists(path) ? path : std::filesystem::path();
}

std::string missing_data_message(const std::string& relative) {
  return "data/" + relative + " is absent: run scripts/fetch-data to test on real data";
}

std::filesystem::path scratch_dir(const std::string& name) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto dir = std::filesystem::temp_directory_path() /
                   ("texsim_test_" + name + "_n" + std::to_string(size));
  if (rank == 0) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return dir;
}

std::vector<std::filesystem::path> temporary_files_under(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> found;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir))
    if (final_name_of_temporary(entry.path().filename().string()))
      found.push_back(entry.path());
  return found;
}

} // namespace texsim::test
