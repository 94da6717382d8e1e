// The study-file reader (lib/study_file): hostile inputs give one-line StudyFileErrors.
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <variant>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/scene_file.h"
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

// scene = "my.toml" said only "expected a table": a path is a scene file next to the study file.
TEST(StudyFile, SceneMayBeAPathRelativeToTheStudyFile) {
  const auto dir = std::filesystem::temp_directory_path() / "vrv_study_file_test";
  std::filesystem::create_directories(dir / "sub");
  std::ofstream(dir / "sub" / "my.toml") << default_scene_toml();
  std::ofstream(dir / "bad.toml") << "[volume]\nmin = 1\n";
  const StudyReader r((dir / "s.toml").string());
  std::string text;
  const Scene s = read_study_scene(r, toml::parse("scene = \"sub/my.toml\"\n"), "", text);
  EXPECT_TRUE(std::holds_alternative<MarschnerLobb>(s.field));
  EXPECT_EQ(text, default_scene_toml());
  auto error = [&](const std::string& doc) {
    try {
      read_study_scene(r, toml::parse(doc), "case[0]", text);
    } catch (const StudyFileError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string prefix = (dir / "s.toml").string() + ": case[0].scene: ";
  std::string msg = error("scene = \"missing.toml\"\n");
  EXPECT_EQ(msg.rfind(prefix + "'missing.toml' is not a scene file", 0), 0u) << msg;
  msg = error("scene = \"bad.toml\"\n");
  EXPECT_EQ(msg.rfind(prefix + (dir / "bad.toml").string() + ": volume.min: ", 0), 0u) << msg;
  msg = error("scene = 3\n");
  EXPECT_EQ(msg, prefix + "expected a [scene] table or the path of a scene file (relative to the study file)");
  std::filesystem::remove_all(dir);
}

// tolerance = 1e308 made a convergence gate pass whatever the observed order.
TEST(StudyFile, OrderToleranceIsBounded) {
  const StudyReader r("s.toml");
  const toml::table doc = toml::parse("a = 0.25\nb = 1e308\nc = 0\nd = 0.5\n");
  EXPECT_EQ(r.order_tolerance(*doc.get("a"), "a"), 0.25);
  EXPECT_EQ(r.order_tolerance(*doc.get("d"), "d"), 0.5);
  for (const char* key : {"b", "c"}) {
    try {
      r.order_tolerance(*doc.get(key), key);
      ADD_FAILURE() << key;
    } catch (const StudyFileError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string("s.toml: ") + key + ": must be in (0, 0.5]", 0), 0u)
          << e.what();
    }
  }
}

// One rule for every study's reference_tol (issue 19: eight readers had four rules, [1e-15, 1e-6]
// in two studies and any positive number in the others).
TEST(StudyFile, ReferenceTolHasOneRule) {
  const StudyReader r("s.toml");
  const auto read = [&](const std::string& text, std::optional<double> fallback) -> std::string {
    try {
      return fmt::format("{:g}", read_reference_tol(r, parse_study_toml(text, "s.toml"), "", fallback));
    } catch (const StudyFileError& e) {
      return e.what();
    }
  };
  EXPECT_EQ(read("", 1e-13), "1e-13");
  EXPECT_EQ(read("", std::nullopt), "s.toml: reference_tol: missing");
  EXPECT_EQ(read("reference_tol = 1e-11\n", 1e-13), "1e-11");
  EXPECT_EQ(read("reference_tol = 1e-16\n", 1e-13), "1e-16");  // allowed: the audit reports the misses
  EXPECT_EQ(read("reference_tol = 1e-6\n", 1e-13), "1e-06");
  EXPECT_EQ(read("reference_tol = 1e-5\n", 1e-13), "s.toml: reference_tol: must be in (0, 1e-06], got 1e-05");
  EXPECT_EQ(read("reference_tol = 0\n", 1e-13), "s.toml: reference_tol: must be in (0, 1e-06], got 0");
  EXPECT_EQ(read("reference_tol = -1e-9\n", 1e-13), "s.toml: reference_tol: must be in (0, 1e-06], got -1e-09");
  EXPECT_EQ(read("reference_tol = 'tight'\n", 1e-13), "s.toml: reference_tol: expected a number");
  const toml::table doc = parse_study_toml("[images]\nreference_tol = 1\n", "s.toml");
  try {
    read_reference_tol(r, *doc["images"].as_table(), "images");
    FAIL();
  } catch (const StudyFileError& e) {
    EXPECT_EQ(std::string(e.what()), "s.toml: images.reference_tol: must be in (0, 1e-06], got 1");
  }
}

}  // namespace
}  // namespace vrv
