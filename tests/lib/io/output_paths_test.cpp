// What an output folder must be before a run replaces it whole (lib/io/output_paths.h), and the
// stderr capture that turns other code's messages into vrv's one line (lib/io/stderr_capture.h).
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "lib/io/output_paths.h"
#include "lib/io/stderr_capture.h"

namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("vrv-output-paths-" + std::to_string(::getpid())) / name;
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p;
}

std::string refusal(const fs::path& dir) {
  try {
    vrv::check_replaceable_dir(dir, "meta.json", "--out");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST(OutputPaths, OnlyAFolderVrvWroteIsReplaced) {
  const fs::path dir = scratch("out");
  EXPECT_EQ(refusal(dir), "");  // missing
  fs::create_directories(dir);
  EXPECT_EQ(refusal(dir), "");  // empty
  std::ofstream(dir / "notes.txt") << "mine";
  EXPECT_EQ(refusal(dir), "--out: " + dir.string() +
                              ": holds files vrv did not write (no meta.json), and a run replaces the whole folder; "
                              "give a new or empty folder, or one an earlier run wrote");
  std::ofstream(dir / "meta.json") << "{}";
  EXPECT_EQ(refusal(dir), "");  // an earlier run's, with whatever else it wrote
  const fs::path file = scratch("a_file");
  std::ofstream(file) << "x";
  EXPECT_EQ(refusal(file), "--out: " + file.string() + ": exists and is not a directory");
}

TEST(StderrCapture, CatchesThisProcessAndItsChildrenThenRestores) {
  vrv::StderrCapture capture;
  std::fputs("first\n", stderr);
  ASSERT_EQ(std::system("echo 'Traceback' >&2; echo 'OSError: [Errno 28] No space left on device' >&2"), 0);
  const std::string said = capture.release();
  EXPECT_EQ(said, "first\nTraceback\nOSError: [Errno 28] No space left on device\n");
  EXPECT_EQ(vrv::last_line(said), "OSError: [Errno 28] No space left on device");
  EXPECT_EQ(vrv::last_line("one line"), "one line");
  EXPECT_EQ(vrv::last_line("\n\n"), "");
}
