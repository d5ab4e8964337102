// Fuzzes the INRIMAGE-4 volume reader: vol::read_inr() on any bytes either returns a grid or
// throws InputError (sizes are checked against a 256 MiB limit before anything is allocated).
#include "core/error.hpp"
#include "fuzz_input_file.hpp"
#include "vol/inr_reader.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  texsim::fuzz::limit_memory();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = texsim::fuzz::write_input(data, size, ".inr");
  try {
    texsim::vol::read_inr(path);
  } catch (const texsim::InputError&) {
    // Refusing malformed input is the expected outcome.
  }
  return 0;
}
