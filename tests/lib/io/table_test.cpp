#include "lib/io/table.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "lib/io/atomic_file.h"
#include "lib/util/not_a_number.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A strict RFC 4180 reader, independent of the writer: records of fields, "\n" line ends.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record;
  std::string field;
  bool quoted = false, field_started = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (quoted) {
      if (ch == '"' && i + 1 < text.size() && text[i + 1] == '"') field += '"', ++i;
      else if (ch == '"') quoted = false;
      else field += ch;
    } else if (ch == '"') {
      EXPECT_FALSE(field_started) << "quote inside an unquoted field at " << i;
      quoted = true;
    } else if (ch == ',') {
      record.push_back(field), field.clear(), field_started = false;
      continue;
    } else if (ch == '\n') {
      record.push_back(field), field.clear(), field_started = false;
      records.push_back(record), record.clear();
      continue;
    } else {
      field += ch;
    }
    field_started = true;
  }
  EXPECT_FALSE(quoted) << "unterminated quote";
  EXPECT_TRUE(field.empty() && record.empty()) << "last record not terminated";
  return records;
}

double parse_double(const std::string& s) {
  char* end = nullptr;
  const double d = std::strtod(s.c_str(), &end);  // std::stod throws on subnormals (ERANGE)
  EXPECT_EQ(end, s.c_str() + s.size()) << s;
  return d;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::size_t code_points(const std::string& s) {
  std::size_t n = 0;
  for (char ch : s) n += (static_cast<unsigned char>(ch) & 0xC0) != 0x80;
  return n;
}

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Table, CsvDoublesRoundTripBitForBit) {
  std::vector<double> values = {0.0,
                                -0.0,
                                0.1,
                                1.0 / 3.0,
                                -2.5e-300,
                                std::numeric_limits<double>::max(),
                                std::numeric_limits<double>::lowest(),
                                std::numeric_limits<double>::min(),
                                std::numeric_limits<double>::denorm_min(),
                                std::nextafter(1.0, 2.0),
                                0.8006225323695293};
  std::mt19937_64 rng(20240501);
  while (values.size() < 2000) {
    const double d = std::bit_cast<double>(rng());
    if (std::isfinite(d)) values.push_back(d);
  }
  Table t({"i", "value"});
  for (std::size_t i = 0; i < values.size(); ++i) t.add_row({static_cast<long>(i), values[i]});

  const auto records = parse_csv(t.to_csv());
  ASSERT_EQ(records.size(), values.size() + 1);
  EXPECT_EQ(records[0], (std::vector<std::string>{"i", "value"}));
  for (std::size_t i = 0; i < values.size(); ++i) {
    ASSERT_EQ(records[i + 1].size(), 2u);
    EXPECT_EQ(records[i + 1][0], std::to_string(i));
    const double back = parse_double(records[i + 1][1]);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(back), std::bit_cast<std::uint64_t>(values[i]))
        << records[i + 1][1] << " for " << values[i];
  }
}

TEST(Table, CsvIntegersAndStdStodReadBack) {
  Table t({"n", "x"});
  t.add_row({-1234567890123L, 0.1});
  t.add_row({7, 1e-5});
  const auto records = parse_csv(t.to_csv());
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[1][0], "-1234567890123");
  EXPECT_EQ(std::stod(records[1][1]), 0.1);
  EXPECT_EQ(std::stod(records[2][1]), 1e-5);
}

TEST(Table, CsvQuotesOnlyWhenNeeded) {
  Table t({"name", "a,b"});
  t.add_row({std::string("plain"), 1L});
  t.add_row({std::string("comma, here"), 2L});
  t.add_row({std::string("say \"hi\""), 3L});
  t.add_row({std::string("two\nlines"), 4L});
  t.add_row({std::string(""), 5L});
  const std::string csv = t.to_csv();
  EXPECT_EQ(csv,
            "name,\"a,b\"\n"
            "plain,1\n"
            "\"comma, here\",2\n"
            "\"say \"\"hi\"\"\",3\n"
            "\"two\nlines\",4\n"
            ",5\n");
  const auto records = parse_csv(csv);
  ASSERT_EQ(records.size(), 6u);
  EXPECT_EQ(records[0][1], "a,b");
  EXPECT_EQ(records[2][0], "comma, here");
  EXPECT_EQ(records[3][0], "say \"hi\"");
  EXPECT_EQ(records[4][0], "two\nlines");
  EXPECT_EQ(records[5][0], "");
}

TEST(Table, MarkdownAlignedWithFormats) {
  Table t({"method", "rate", "error", "time"});
  t.set_format("error", "{:.3e}");
  t.set_format("time", "{:.4f}");
  t.add_row({std::string("alpha"), 1L, 1.23456e-5, 0.5});
  t.add_row({std::string("lee–newman"), 16L, 2.0, 12.345678});
  t.add_row({std::string("a|b"), -3L, -1e-300, 100.0});
  const std::string md = t.to_markdown();
  // Every line has the same pipes at the same places (widths in code points, so "–" counts once).
  const auto rows = lines(md);
  ASSERT_EQ(rows.size(), 5u);
  for (const auto& row : rows) EXPECT_EQ(code_points(row), code_points(rows[0])) << row;
  EXPECT_EQ(rows[0], "| method     | rate | error       | time     |");
  EXPECT_EQ(rows[1], "| :--------- | ---: | ----------: | -------: |");
  EXPECT_EQ(rows[2], "| alpha      |    1 |   1.235e-05 |   0.5000 |");
  EXPECT_EQ(rows[3], "| lee–newman |   16 |   2.000e+00 |  12.3457 |");
  EXPECT_EQ(rows[4], "| a\\|b       |   -3 | -1.000e-300 | 100.0000 |");
}

TEST(Table, MarkdownDefaultFormatIsSixSignificantDigits) {
  Table t({"x"});
  t.add_row({1.0 / 3.0});
  t.add_row({123456789.0});
  const auto rows = lines(t.to_markdown());
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[2], "|    0.333333 |");
  EXPECT_EQ(rows[3], "| 1.23457e+08 |");
}

TEST(Table, BadFormatsAndUnknownColumnsAreRejected) {
  Table t({"x"});
  EXPECT_THROW(t.set_format("x", "{:d}"), std::invalid_argument);     // a double cannot take it
  EXPECT_THROW(t.set_format("x", "{:.3f"), std::invalid_argument);    // malformed
  EXPECT_THROW(t.set_format("x", "value"), std::invalid_argument);    // ignores the value
  EXPECT_THROW(t.set_format("y", "{:.3f}"), std::invalid_argument);   // no such column
  EXPECT_THROW(t.allow_missing("y"), std::invalid_argument);
  EXPECT_THROW(Table({}), std::invalid_argument);
  EXPECT_THROW(Table({"a", "a"}), std::invalid_argument);
  EXPECT_THROW(Table({"a", ""}), std::invalid_argument);
}

TEST(Table, LatexBooktabsWithEscaping) {
  Table t({"scene_name", "n", "error"});
  t.set_format("error", "{:.2e}");
  t.add_row({std::string("50% & #1 $x$ {a} ~b^c \\d"), 4L, 1.5e-7});
  t.add_row({std::string("plain"), -2L, -0.25});
  const std::string tex = t.to_latex();
  EXPECT_EQ(tex,
            "\\begin{tabular}{lrr}\n"
            "  \\toprule\n"
            "  scene\\_name & n & error \\\\\n"
            "  \\midrule\n"
            "  50\\% \\& \\#1 \\$x\\$ \\{a\\} \\textasciitilde{}b\\textasciicircum{}c \\textbackslash{}d & $4$ & "
            "$1.50 \\times 10^{-7}$ \\\\\n"
            "  plain & $-2$ & $-2.50 \\times 10^{-1}$ \\\\\n"
            "  \\bottomrule\n"
            "\\end{tabular}\n");
}

TEST(Table, LatexCaptionLabelAndHeaders) {
  Table t({"dt", "ratio"});
  t.set_format("ratio", "{:.1f}%");
  t.add_row({0.5, 12.25});
  LatexStyle style;
  style.caption = "Error against $\\Delta t$";
  style.label = "tab:error";
  style.headers = {{"dt", "$\\Delta t$"}};
  const std::string tex = t.to_latex(style);
  EXPECT_EQ(tex,
            "\\begin{table}[htbp]\n"
            "  \\centering\n"
            "  \\caption{Error against $\\Delta t$}\n"
            "  \\label{tab:error}\n"
            "  \\begin{tabular}{rr}\n"
            "    \\toprule\n"
            "    $\\Delta t$ & ratio \\\\\n"
            "    \\midrule\n"
            "    $0.5$ & 12.2\\% \\\\\n"
            "    \\bottomrule\n"
            "  \\end{tabular}\n"
            "\\end{table}\n");
  style.headers = {{"nope", "x"}};
  EXPECT_THROW(t.to_latex(style), std::invalid_argument);
}

TEST(Table, NonFiniteRejectedNamingTheColumn) {
  Table t({"method", "error"});
  for (double bad : {kNaN, kInf, -kInf}) {
    try {
      t.add_row({std::string("alpha"), bad});
      FAIL() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'error'"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(t.size(), 0u);  // nothing half added
}

TEST(Table, AllowMissingWritesEmptyAndNa) {
  Table t({"method", "order"});
  t.allow_missing("order");
  t.add_row({std::string("alpha"), kNaN});
  t.add_row({std::string("riemann"), 2.0});
  t.add_row({std::string("beta"), kInf});
  EXPECT_EQ(t.to_csv(), "method,order\nalpha,\nriemann,2\nbeta,\n");
  const std::string md = t.to_markdown();
  EXPECT_NE(md.find("| alpha   |   n/a |"), std::string::npos) << md;
  EXPECT_NE(md.find("| riemann |     2 |"), std::string::npos) << md;
  EXPECT_EQ(md.find("nan"), std::string::npos);
  EXPECT_EQ(md.find("inf"), std::string::npos);
  const std::string tex = t.to_latex();
  EXPECT_NE(tex.find("alpha & n/a \\\\"), std::string::npos) << tex;
  EXPECT_EQ(tex.find("nan"), std::string::npos);
  EXPECT_NE(tex.find("{lr}"), std::string::npos) << tex;
}

TEST(Table, WrongColumnCountThrows) {
  Table t({"a", "b"});
  EXPECT_THROW(t.add_row({1L}), std::invalid_argument);
  EXPECT_THROW(t.add_row({1L, 2L, 3L}), std::invalid_argument);
  t.add_row({1L, 2.0});
  EXPECT_EQ(t.size(), 1u);
}

TEST(Table, EmptyTableHasHeaderOnly) {
  Table t({"a", "b"});
  EXPECT_EQ(t.to_csv(), "a,b\n");
  EXPECT_EQ(t.to_markdown(), "| a   | b   |\n| --: | --: |\n");
}

// Atomic writes.

class TableAtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("vrv_atomic_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    return out;
  }
  fs::path dir_;
};

TEST_F(TableAtomicFile, WritesContentAndLeavesNoTemporary) {
  const fs::path file = dir_ / "results.csv";
  const std::string contents = std::string("a,b\n1,2\n") + std::string(1 << 20, 'x') + '\0' + "end";
  write_file_atomically(file, contents);
  EXPECT_EQ(read(file), contents);
  EXPECT_EQ(entries(), std::vector<std::string>{"results.csv"});
}

TEST_F(TableAtomicFile, ReplacesAnExistingFileWhole) {
  const fs::path file = dir_ / "meta.json";
  write_file_atomically(file, std::string(10000, 'a'));
  write_file_atomically(file, "short");
  EXPECT_EQ(read(file), "short");
  write_file_atomically(file, "");
  EXPECT_EQ(read(file), "");
  EXPECT_EQ(fs::file_size(file), 0u);
  EXPECT_EQ(entries(), std::vector<std::string>{"meta.json"});
}

TEST_F(TableAtomicFile, MissingDirectoryThrowsNamingThePath) {
  const fs::path file = dir_ / "no_such_dir" / "results.csv";
  try {
    write_file_atomically(file, "x");
    FAIL() << "wrote into a missing directory";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(file.string() + ": cannot write: ", 0), 0u) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(dir_ / "no_such_dir"));
}

TEST_F(TableAtomicFile, FailedRenameRemovesTemporaryAndKeepsTarget) {
  // The target is a non-empty directory: the temporary is written, the rename fails.
  const fs::path target = dir_ / "taken";
  fs::create_directories(target / "inside");
  EXPECT_THROW(write_file_atomically(target, "x"), std::runtime_error);
  EXPECT_EQ(entries(), std::vector<std::string>{"taken"});
  EXPECT_TRUE(fs::is_directory(target / "inside"));
}

// Writers of one path at once (a reference cache shared by processes and machines; here
// threads, which share a pid): each renames a whole file of its own, none fails, and a reader
// meanwhile sees a whole file or none.  With the temporary named by the pid alone, the writers
// truncated and renamed each other's temporary.
TEST_F(TableAtomicFile, ConcurrentWritersOfOnePathEachRenameAWholeFile) {
  const fs::path file = dir_ / "reference-cache.bin";
  constexpr int kWriters = 6, kWrites = 20;
  std::vector<std::string> contents;
  for (int w = 0; w < kWriters; ++w) contents.push_back(std::string(200000 + 1000 * w, static_cast<char>('a' + w)));
  std::atomic<int> failures{0}, torn{0};
  std::atomic<bool> writing{true};
  std::thread reader([&] {
    while (writing) {
      std::ifstream in(file, std::ios::binary);
      if (!in) continue;
      const std::string got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (std::find(contents.begin(), contents.end(), got) == contents.end()) ++torn;
    }
  });
  std::vector<std::thread> writers;
  for (int w = 0; w < kWriters; ++w)
    writers.emplace_back([&, w] {
      for (int i = 0; i < kWrites; ++i) try {
          write_file_atomically(file, contents[w]);
        } catch (const std::runtime_error&) {
          ++failures;
        }
    });
  for (auto& t : writers) t.join();
  writing = false;
  reader.join();
  EXPECT_EQ(failures, 0);
  EXPECT_EQ(torn, 0);
  EXPECT_NE(std::find(contents.begin(), contents.end(), read(file)), contents.end());
  EXPECT_EQ(entries(), std::vector<std::string>{"reference-cache.bin"});
}

TEST(TemporarySuffix, NamesThePidAndDiffersOnEveryCall) {
  const std::string a = temporary_suffix(), b = temporary_suffix();
  EXPECT_EQ(a.rfind(".tmp." + std::to_string(::getpid()) + ".", 0), 0u) << a;
  EXPECT_NE(a, b);
}

}  // namespace
}  // namespace vrv
