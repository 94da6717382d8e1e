// Staging, publishing and checkpoints of a study run (studies/engine/staging, checkpoint).
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "studies/engine/checkpoint.h"
#include "studies/engine/interrupt.h"
#include "studies/engine/staging.h"

namespace vrv {
namespace {
namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("vrv_staging_test_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(StudyStaging, PublishReplacesThePreviousRunWhole) {
  const fs::path out = fresh_dir("publish");
  fs::create_directories(out / "s");
  std::ofstream(out / "s" / "old.csv") << "old";
  {
    StudyStaging st(out, "s", false);
    EXPECT_EQ(st.dir(), out / ".s.partial");
    std::ofstream(st.dir() / "new.csv") << "new";
    // Until published, the previous run is what the folder holds.
    EXPECT_EQ(read(out / "s" / "old.csv"), "old");
    st.publish();
  }
  EXPECT_FALSE(fs::exists(out / "s" / "old.csv"));
  EXPECT_EQ(read(out / "s" / "new.csv"), "new");
  EXPECT_FALSE(fs::exists(out / ".s.partial"));
  EXPECT_FALSE(fs::exists(out / ".s.done"));
  EXPECT_FALSE(fs::exists(out / ".s.lock"));
}

TEST(StudyStaging, AnUnpublishedRunLeavesTheResultsAndItsCheckpoints) {
  const fs::path out = fresh_dir("unpublished");
  fs::create_directories(out / "s");
  std::ofstream(out / "s" / "old.csv") << "old";
  {
    StudyStaging st(out, "s", false);
    std::ofstream(st.dir() / "part.txt") << "1";
  }
  EXPECT_EQ(read(out / "s" / "old.csv"), "old");
  {
    StudyStaging st(out, "s", true);  // --resume continues it
    EXPECT_TRUE(st.resumed());
    EXPECT_TRUE(fs::exists(st.dir() / "part.txt"));
  }
  {
    StudyStaging st(out, "s", false);  // a fresh run starts empty
    EXPECT_FALSE(st.resumed());
    EXPECT_FALSE(fs::exists(st.dir() / "part.txt"));
  }
}

TEST(StudyStaging, StaleLeftoversAreRemoved) {
  const fs::path out = fresh_dir("stale");
  fs::create_directories(out / ".s.done");  // killed between publishing and removing the old run
  fs::create_directories(out / ".s.partial");
  std::ofstream(out / ".s.partial" / "t.csv.tmp.999999999") << "x";  // no such process
  std::ofstream(out / ".s.partial" / "keep.txt") << "x";
  StudyStaging st(out, "s", true);
  EXPECT_FALSE(fs::exists(out / ".s.done"));
  EXPECT_FALSE(fs::exists(st.dir() / "t.csv.tmp.999999999"));
  EXPECT_TRUE(fs::exists(st.dir() / "keep.txt"));
}

TEST(StudyStaging, TwoRunsOfOneStudyAreRefused) {
  const fs::path out = fresh_dir("lock");
  StudyStaging first(out, "s", false);
  try {
    StudyStaging second(out, "s", false);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("another vrv study is writing them"), std::string::npos) << e.what();
  }
}

TEST(StudyStaging, ResultsPathThatIsAFileIsRefused) {
  const fs::path out = fresh_dir("file");
  std::ofstream(out / "s") << "x";
  EXPECT_THROW(StudyStaging(out, "s", false), std::runtime_error);
}

TEST(Checkpoints, StoreExactlyAndReuseOnResume) {
  const fs::path dir = fresh_dir("checkpoints") / "checkpoints";
  const std::vector<double> v{0.1, -0.0, 5e-324, 1e308, std::numeric_limits<double>::infinity(),
                              std::numeric_limits<double>::quiet_NaN()};
  int calls = 0;
  auto compute = [&] { ++calls; return v; };
  {
    Checkpoints c(dir, "file text; quick", false);
    c.get("a_1", compute);
    EXPECT_EQ(c.computed(), 1);
  }
  Checkpoints c(dir, "file text; quick", true);
  const std::vector<double> back = c.get("a_1", compute);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(c.reused(), 1);
  ASSERT_EQ(back.size(), v.size());
  for (std::size_t i = 0; i + 1 < v.size(); ++i) {
    EXPECT_EQ(back[i], v[i]);
    EXPECT_EQ(std::signbit(back[i]), std::signbit(v[i]));
  }
  EXPECT_TRUE(std::isnan(back.back()));
  EXPECT_THROW(c.get("a/b", compute), std::logic_error);
}

// A stored checkpoint carries its count and a CRC-64: one cut to its end line (SIGSEGV before),
// with values removed (a wrong table published before) or edited (0x1p+1000 samples overflowed a
// cast), or holding another count than its computation gives, is refused naming the file.
TEST(Checkpoints, DamagedOrMisshapenCheckpointsAreRefusedNamingTheFile) {
  const fs::path dir = fresh_dir("damaged") / "checkpoints";
  const std::vector<double> v{0.25, 3, 7};
  { Checkpoints c(dir, "study", false); c.get("k", [&] { return v; }); }
  const std::string good = [&] { std::ifstream in(dir / "k.txt"); std::stringstream s; s << in.rdbuf(); return s.str(); }();
  const auto refusal = [&](const std::string& text, std::optional<std::size_t> expected = std::nullopt) {
    std::ofstream(dir / "k.txt") << text;
    Checkpoints c(dir, "study", true);
    try {
      c.get("k", [&] { return v; }, expected);
    } catch (const StudyResumeError& e) {
      return std::string(e.what());
    }
    return std::string("(used)");
  };
  const std::string file = (dir / "k.txt").string();
  EXPECT_EQ(refusal("end\n").rfind(file + ": 0 values and their checksum do not match", 0), 0u) << refusal("end\n");
  EXPECT_NE(refusal(good.substr(good.find('\n') + 1)).find("do not match its end line"), std::string::npos);
  std::string edited = good;
  edited.replace(edited.find("0x1.8p+1"), 8, "0x1p+1000");
  EXPECT_NE(refusal(edited).find("changed or damaged"), std::string::npos);
  EXPECT_NE(refusal("x\n" + good).find("line 1 is not a number"), std::string::npos);
  EXPECT_NE(refusal(good, 4).find(file + ": 3 values, expected 4"), std::string::npos);
  EXPECT_EQ(refusal(good, 3), "(used)");
  std::ofstream(dir / "other.txt") << good;  // a good file under another key
  Checkpoints c(dir, "study", true);
  EXPECT_THROW(c.get("other", [&] { return v; }), StudyResumeError);
}

TEST(Checkpoints, ItemsResumeAtTheFirstMissingBlock) {
  const fs::path dir = fresh_dir("items") / "checkpoints";
  std::atomic<long> calls{0}, advanced{0};
  auto item = [&](long i, std::span<double> o) {
    ++calls;
    o[0] = static_cast<double>(i);
    o[1] = 1.0 / static_cast<double>(i + 3);
  };
  auto advance = [&](long n) { advanced += n; };
  std::vector<double> first;
  {
    Checkpoints c(dir, "items", false);
    first = checkpointed_items(&c, "px", 10, 4, 2, item, advance);  // blocks 0-3, 4-7, 8-9
    EXPECT_EQ(c.computed(), 3);
  }
  EXPECT_EQ(calls, 10);
  EXPECT_EQ(advanced, 10);
  ASSERT_EQ(first.size(), 20u);
  for (long i = 0; i < 10; ++i) {
    EXPECT_EQ(first[2 * i], static_cast<double>(i));
    EXPECT_EQ(first[2 * i + 1], 1.0 / static_cast<double>(i + 3));
  }
  fs::remove(dir / "px.4.txt");  // as if killed before the second block was stored
  calls = advanced = 0;
  Checkpoints c(dir, "items", true);
  EXPECT_EQ(checkpointed_items(&c, "px", 10, 4, 2, item, advance), first);
  EXPECT_EQ(calls, 4);  // the missing block alone
  EXPECT_EQ(advanced, 10);
  EXPECT_EQ(c.reused(), 2);
  // A block stored with another width is an error, not a silent misreading.
  EXPECT_THROW(checkpointed_items(&c, "px", 10, 4, 3, item), StudyResumeError);
  // Without checkpoints: computed every time, the same values.
  EXPECT_EQ(checkpointed_items(nullptr, "px", 10, 4, 2, item), first);
}

// The image loop's blocks, one checkpoint each: a resumed loop computes only the missing block.
TEST(Checkpoints, ImageBlocksResumeAtTheMissingBlock) {
  const fs::path dir = fresh_dir("blocks") / "checkpoints";
  Camera camera;
  camera.width = 4;
  camera.height = 3;
  ImageLoopHooks hooks;
  hooks.block = camera.width;
  std::atomic<long> calls{0};
  auto pixel = [&](const Ray& ray, std::span<double> out) {
    ++calls;
    out[0] = ray.direction[0];
    out[1] = 1.0 / (3.0 + ray.direction[1]);
  };
  std::vector<double> first;
  {
    Checkpoints c(dir, "blocks", false);
    first = image_records(camera, {}, 2, pixel, hooks, checkpoint_blocks(&c, "px"));
    EXPECT_EQ(c.computed(), 3);
  }
  EXPECT_EQ(calls, 12);
  ASSERT_EQ(first.size(), 24u);
  EXPECT_NE(first[0], first[2]);
  fs::remove(dir / "px.4.txt");  // as if killed before the second row was stored
  calls = 0;
  Checkpoints c(dir, "blocks", true);
  EXPECT_EQ(image_records(camera, {}, 2, pixel, hooks, checkpoint_blocks(&c, "px")), first);
  EXPECT_EQ(calls, 4);  // the missing row alone
  EXPECT_EQ(c.reused(), 2);
  EXPECT_EQ(image_records(camera, {}, 2, pixel, hooks, checkpoint_blocks(nullptr, "px")), first);
}

TEST(Checkpoints, RecordsRoundTripOrComputeOnce) {
  const fs::path dir = fresh_dir("records") / "checkpoints";
  struct R {
    double x;
    long n;
  };
  int calls = 0;
  auto compute = [&] { ++calls; return std::vector<R>{{0.5, 3}, {-2.0, 7}}; };
  auto encode = [](const R& r, std::vector<double>& out) { out.insert(out.end(), {r.x, double(r.n)}); };
  auto decode = [](std::span<const double> v) { return R{v[0], static_cast<long>(v[1])}; };
  { Checkpoints c(dir, "records", false); checkpointed_records<R>(&c, "r", 2, compute, encode, decode); }
  Checkpoints c(dir, "records", true);
  const std::vector<R> back = checkpointed_records<R>(&c, "r", 2, compute, encode, decode);
  EXPECT_EQ(calls, 1);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].x, -2.0);
  EXPECT_EQ(back[1].n, 7);
  EXPECT_THROW(checkpointed_records<R>(&c, "r", 3, compute, encode, decode), StudyResumeError);
}

TEST(Checkpoints, ResumingAnotherFileOrVariantIsRefused) {
  const fs::path dir = fresh_dir("identity") / "checkpoints";
  { Checkpoints c(dir, "text A", false); }
  EXPECT_THROW(Checkpoints(dir, "text B", true), StudyResumeError);
  EXPECT_NO_THROW(Checkpoints(dir, "text B", false));  // a fresh run takes the folder over
}

TEST(Interrupt, OnlyStaleTemporaryFilesAreRemoved) {
  const fs::path d = fresh_dir("tmpfiles");
  std::ofstream(d / "a.csv.tmp.999999999") << "x";                                 // dead process
  std::ofstream(d / "b.pdf.tmp.999999998.pdf") << "x";                             // the plot script's
  std::ofstream(d / ("c.csv.tmp." + std::to_string(::getppid()))) << "x";          // a live process
  std::ofstream(d / "d.csv") << "x";
  EXPECT_EQ(remove_temporary_files(d, true), 2);
  EXPECT_TRUE(fs::exists(d / ("c.csv.tmp." + std::to_string(::getppid()))));
  EXPECT_TRUE(fs::exists(d / "d.csv"));
}

}  // namespace
}  // namespace vrv
