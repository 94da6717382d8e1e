#include "lib/io/error_line.h"

#include <string>

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(ErrorLine, ShortPartsAreKeptAndLineBreaksBecomeSpaces) {
  EXPECT_EQ(error_line("a.toml", "camera.width", "must be\npositive"), "a.toml: camera.width: must be positive");
}

TEST(ErrorLine, LongPartsAreCutWithTheirLength) {
  const std::string line = error_line("f.toml", std::string(5000, 'x'), "unknown key");
  EXPECT_EQ(line, "f.toml: " + std::string(kMaxErrorPart, 'x') + "... (5000 bytes): unknown key");
}

TEST(ErrorLine, CutKeepsWholeUtf8Characters) {
  std::string s;
  for (int i = 0; i < 300; ++i) s += "\xC3\xA9";  // é: two bytes each
  const std::string cut = cut_for_message(s, 201);
  EXPECT_EQ(cut, s.substr(0, 200) + "... (600 bytes)");
}

}  // namespace
}  // namespace vrv
