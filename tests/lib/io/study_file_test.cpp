// The study-file reader (lib/io/study_file): hostile inputs give one-line StudyFileErrors.
#include <string>

#include <gtest/gtest.h>

#include "lib/study_file.h"

namespace vrv {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_study_toml(text, "s.toml");
  } catch (const StudyFileError& e) {
    return e.what();
  }
  return "";
}

// toml++ recurses once per key level: a key of 30,000 dotted parts crashed `vrv study` (SIGSEGV).
TEST(StudyFile, DeeplyDottedKeyIsAnErrorNotAStackOverflow) {
  std::string deep = "a";
  for (int i = 0; i < 30000; ++i) deep += ".a";
  for (const std::string& text : {deep + " = 1\n", "[" + deep + "]\n", "kind = 'x'\n" + deep + " = 1\n"}) {
    const std::string msg = error_of(text);
    EXPECT_EQ(msg.rfind("s.toml: (syntax): line ", 0), 0u) << msg.substr(0, 200);
    EXPECT_NE(msg.find("nested too deeply"), std::string::npos) << msg.substr(0, 200);
  }
  // Ordinary dotted keys still parse.
  EXPECT_EQ(error_of("a.b.c = 1\n[x.y.z]\nw = 2\n"), "");
}

// A 10 MB table name gave a 10 MB error line: every part of the line is cut to a bound.
TEST(StudyFile, HugeKeyGivesAShortLine) {
  const std::string name(10'000'000, 'k');
  const StudyReader r("s.toml");
  const toml::table doc = parse_study_toml("[" + name + "]\nx = 1\n", "s.toml");
  try {
    r.check_keys(doc, "", {"kind", "name"});
    FAIL();
  } catch (const StudyFileError& e) {
    const std::string msg = e.what();
    EXPECT_LT(msg.size(), 1200u);
    EXPECT_EQ(msg.rfind("s.toml: kkkk", 0), 0u) << msg;
    EXPECT_NE(msg.find("(10000000 bytes): unknown key"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace vrv
