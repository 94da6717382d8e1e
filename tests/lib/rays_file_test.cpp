#include "lib/rays_file.h"

#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>
#include <string>

namespace vrv {
namespace {

std::string error_of(const std::string& text) {
  std::istringstream in(text);
  try {
    read_rays(in, "r.jsonl");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RaysFile, ReadsRaysWithLineNumbersAndIds) {
  std::istringstream in(
      "{\"origin\": [-3, 0.5, 0], \"direction\": [2, 0, 0], \"id\": \"a\"}\n"
      "\n"
      "  \t\n"
      "{\"direction\": [0, 0, 1e-300], \"origin\": [1e300, 0, -5]}\n"
      "{\"origin\": [0, 0, 0], \"direction\": [0, 3, 4], \"id\": {\"k\": [1, 2]}}\r\n");
  const auto rays = read_rays(in, "r.jsonl");
  ASSERT_EQ(rays.size(), 3u);
  EXPECT_EQ(rays[0].line, 1);
  EXPECT_EQ(rays[1].line, 4);
  EXPECT_EQ(rays[2].line, 5);
  EXPECT_EQ(rays[0].id, "a");
  EXPECT_TRUE(rays[1].id.is_null());
  EXPECT_EQ(rays[2].id, nlohmann::json::parse("{\"k\": [1, 2]}"));
  EXPECT_EQ(rays[0].ray.direction, Vec3(1, 0, 0));  // normalised
  EXPECT_EQ(rays[1].ray.direction, Vec3(0, 0, 1));  // tiny directions normalise too
  EXPECT_EQ(rays[1].ray.origin, Vec3(1e300, 0, -5));
  EXPECT_DOUBLE_EQ(rays[2].ray.direction[1], 0.6);
}

TEST(RaysFile, EmptyInputHasNoRays) {
  std::istringstream in("\n\n");
  EXPECT_TRUE(read_rays(in, "r.jsonl").empty());
}

// Each bad line: the file, the line number and the reason (not "not a JSON object").
TEST(RaysFile, BadLinesNameLineAndReason) {
  const std::string good = "{\"origin\": [-3, 0, 0], \"direction\": [1, 0, 0]}\n";
  EXPECT_EQ(error_of(good + "{\"origin\": [NaN, 0, 0], \"direction\": [1, 0, 0]}"),
            "r.jsonl:2: column 13: NaN is not a JSON number (NaN and infinities cannot be given)");
  EXPECT_EQ(error_of(good + "{\"origin\": [0, 0, 0], \"direction\": [1, -Infinity, 0]}"),
            "r.jsonl:2: column 40: -Infinity is not a JSON number (NaN and infinities cannot be given)");
  EXPECT_EQ(error_of(good + "{\"origin\": [0, nan, 0], \"direction\": [1, 0, 0]}"),
            "r.jsonl:2: column 16: nan is not a JSON number (NaN and infinities cannot be given)");
  EXPECT_EQ(error_of(good + "{\"origin\": [1e999, 0, 0], \"direction\": [1, 0, 0]}"),
            "r.jsonl:2: 1e999 is beyond the range of a double");
  EXPECT_EQ(error_of(good + "{\"origin\": [1, 0, 0], \"direction\": [1, 0"),
            "r.jsonl:2: truncated: the line ends before its JSON object is complete");
  EXPECT_EQ(error_of("[1, 2, 3]"),
            "r.jsonl:1: expected a JSON object {\"origin\": [x, y, z], \"direction\": [x, y, z]}, got array");
  EXPECT_EQ(error_of("{\"origin\": [0, 0, 0], \"direction\": [1, 0, 0]} x"),
            "r.jsonl:1: column 47: invalid JSON: invalid literal; last read: '0]} x'; expected end of input");
  EXPECT_EQ(error_of("{\"origin\": [0, 0, 0], \"direction\": [1, 0, 0], \"dir\": 1}"),
            "r.jsonl:1: unknown key 'dir' (origin, direction and id are read)");
  EXPECT_EQ(error_of("{\"origin\": [0, 0], \"direction\": [1, 0, 0]}"),
            "r.jsonl:1: origin: expected an array of three numbers");
  EXPECT_EQ(error_of("{\"origin\": [0, 0, 0]}"), "r.jsonl:1: direction: missing");
  EXPECT_EQ(error_of("{\"origin\": [0, \"1\", 0], \"direction\": [1, 0, 0]}"),
            "r.jsonl:1: origin[1]: not a number");
  EXPECT_EQ(error_of("{\"origin\": [0, 0, 0], \"direction\": [0, 0, 0]}"),
            "r.jsonl:1: direction: ray direction is zero");
}

// A hostile key is cut, so an error stays a line.
TEST(RaysFile, LongKeysAreCut) {
  const std::string e = error_of("{\"" + std::string(100000, 'k') + "\": 1}");
  EXPECT_LT(e.size(), 120u) << e;
  EXPECT_NE(e.find("unknown key 'kkkk"), std::string::npos) << e;
}

// Copying or printing an id recurses once per level: a 70,000-deep id overflowed the stack
// (issue 22).  Nesting is bounded while parsing; an id 99 levels deep passes through.
TEST(RaysFile, DeeplyNestedIdIsAnErrorNotAStackOverflow) {
  const auto line = [](int depth) {
    return "{\"origin\": [-3, 0, 0], \"direction\": [1, 0, 0], \"id\": " + std::string(depth, '[') +
           std::string(depth, ']') + "}\n";
  };
  EXPECT_EQ(error_of(line(1) + line(70000)), "r.jsonl:2: nested more than 100 arrays or objects deep");
  EXPECT_EQ(error_of(line(100)), "r.jsonl:1: nested more than 100 arrays or objects deep");
  std::istringstream in(line(99));
  EXPECT_EQ(read_rays(in, "r.jsonl").size(), 1u);
}

// The second value of a repeated key was taken silently (issue 22); inside an id too, since the id
// is passed through whole.
TEST(RaysFile, ARepeatedKeyIsAnError) {
  EXPECT_EQ(error_of("{\"origin\": [-3, 0, 0], \"direction\": [1, 0, 0], \"origin\": [-3, 0.5, 0]}"),
            "r.jsonl:1: key 'origin' given twice");
  EXPECT_EQ(error_of("{\"origin\": [-3, 0, 0], \"direction\": [1, 0, 0], \"id\": {\"a\": 1, \"b\": {\"a\": 2}, \"a\": 3}}"),
            "r.jsonl:1: key 'a' given twice");
  std::istringstream in("{\"origin\": [-3, 0, 0], \"direction\": [1, 0, 0], \"id\": [{\"a\": 1}, {\"a\": 2}]}");
  EXPECT_EQ(read_rays(in, "r.jsonl").size(), 1u);
}

// `--rays /dev/zero` read one endless line into memory (issue 22): a line is at most 1 MiB.
TEST(RaysFile, ALineLongerThanOneMebibyteIsAnError) {
  const std::string ray = "{\"origin\": [-3, 0, 0], \"direction\": [1, 0, 0]}";
  EXPECT_EQ(error_of(ray + "\n" + std::string(3 << 20, '\0')),
            "r.jsonl:2: longer than 1048576 bytes (1 MiB), the longest line read");
  const std::string padded = ray + std::string((1 << 20) - ray.size(), ' ');  // exactly 1 MiB
  std::istringstream in(padded + "\n" + padded);
  EXPECT_EQ(read_rays(in, "r.jsonl").size(), 2u);
}

}  // namespace
}  // namespace vrv
