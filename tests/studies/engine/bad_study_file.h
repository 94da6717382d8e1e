#pragma once
// The study parsers' tests: a bad study file and the start of the one-line error it must give.
#include <cstddef>
#include <string>

#include <gtest/gtest.h>

#include "lib/study_file.h"

namespace vrv::study_test {

struct BadFile {
  std::string text, prefix;
};

// What parse(text, "bad.toml", "bad") throws as a StudyFileError, or "(no error)".
template <class Parse>
std::string study_error(Parse parse, const std::string& text) {
  try {
    parse(text, "bad.toml", "bad");
  } catch (const StudyFileError& e) {
    return e.what();
  }
  return "(no error)";
}

template <class Parse, std::size_t N>
void expect_one_line_errors(Parse parse, const BadFile (&cases)[N]) {
  for (const auto& c : cases) {
    const std::string e = study_error(parse, c.text);
    EXPECT_TRUE(e.starts_with(c.prefix)) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

}  // namespace vrv::study_test
