// Fuzzes one mesh format (TEXSIM_FUZZ_EXTENSION): geom::read_raw_mesh() on any bytes either
// returns a mesh or throws InputError; it never crashes, hangs or lets VTK read past a buffer.
#include "core/error.hpp"
#include "fuzz_input_file.hpp"
#include "geom/mesh_reader.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  texsim::fuzz::limit_memory();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = texsim::fuzz::write_input(data, size, TEXSIM_FUZZ_EXTENSION);
  try {
    texsim::geom::read_raw_mesh(path);
  } catch (const texsim::InputError&) {
    // Refusing malformed input is the expected outcome.
  }
  return 0;
}
