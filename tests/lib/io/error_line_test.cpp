#include "lib/io/error_line.h"

#include <string>

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(ErrorLine, ShortPartsAreKeptAndLineBreaksBecomeSpaces) {
  EXPECT_EQ(error_line("a.toml", "camera.width", "must be\npositive"), "a.toml: camera.width: must be positive");
}

// A header's ESC sequence quoted in a reason was written to the terminal as it was.
TEST(ErrorLine, ControlBytesAreWrittenAsEscapes) {
  EXPECT_EQ(error_line("a.mha", "ElementType", "MET_\x1b[31mFLOAT\tnot supported\x7f"),
            "a.mha: ElementType: MET_\\x1b[31mFLOAT not supported\\x7f");
  EXPECT_EQ(one_line(std::string("a\0b\x01", 4)), "a\\x00b\\x01");
  EXPECT_EQ(one_line("caf\xC3\xA9 ok "), "caf\xC3\xA9 ok");  // UTF-8 is kept
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
