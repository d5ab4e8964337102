// Fuzzes the config reader: any text either gives a document whose keys can be read, hashed and
// emitted, or an InputError. Crashes, hangs, leaks and other exceptions are findings.
#include "core/config.hpp"
#include "core/memory_budget.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace texsim;
  try {
    auto document =
        ConfigDocument::parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
    auto root = document.root();
    root.get<std::string>("pipeline", "");
    root.get<std::uint64_t>("seed", 1);
    root.section("output").get<int>("every", 1, positive_int());
    root.section("mesh_prep").section("input").get<double>("scale", 1.0, positive());
    root.section("fem_rd").section("time").get<std::vector<double>>("dims", {});
    root.string_map("petsc");
    for (const auto& key : root.keys())
      root.has(key);
    document.result_hash({"fem_rd.time.steps"});
    const std::string text = document.emit();
    ConfigDocument::parse(text, "fuzz.yaml").set_override("output.dir=out");
    document.check_unknown_keys();
  } catch (const InputError&) {
    // Refusing malformed input is the expected outcome.
  }
  return 0;
}
