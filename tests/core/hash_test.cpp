// FNV-1a: the published test vectors, and continuing from a state hashes the concatenation (what
// solid_synthesis' exemplar content hash relies on to skip a copy of the exemplar).
#include "core/hash.hpp"

#include <gtest/gtest.h>

#include <string>

namespace texsim {
namespace {

TEST(Fnv1a64, PublishedTestVectors) {
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ULL);
  EXPECT_EQ(hex64(0xaf63dc4c8601ec8cULL), "af63dc4c8601ec8c");
}

TEST(Fnv1a64, ContinuingFromAStateHashesTheConcatenation) {
  const std::string header = "128x128x128x3:", body(1000, '\x7f');
  EXPECT_EQ(fnv1a64(body, fnv1a64(header)), fnv1a64(header + body));
  EXPECT_NE(fnv1a64(body), fnv1a64(header + body));
}

} // namespace
} // namespace texsim
