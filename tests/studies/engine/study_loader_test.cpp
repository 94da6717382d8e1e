// studies/engine/study_loader: the memory a study may take covers what its file's estimate cannot
// see before reading (a volume file, a scene file's grid), spent as each is read.
#include "studies/engine/study_loader.h"

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace vrv {
namespace study_loader_test {  // named: the unity build joins test files

namespace fs = std::filesystem;

fs::path scratch() {
  const fs::path d = fs::temp_directory_path() / ("vrv_study_loader_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

// A 9^3 NRRD of float64 (5832 bytes of samples) or int16 samples (1458 bytes, read through a table
// of 65536 doubles: 512 KiB).
template <class T>
void write_volume(const fs::path& file, const char* type) {
  std::ofstream out(file, std::ios::binary);
  out << "NRRD0004\ntype: " << type << "\ndimension: 3\nsizes: 9 9 9\nendian: little\nencoding: raw\n\n";
  for (int i = 0; i < 9 * 9 * 9; ++i) {
    const T v = static_cast<T>(i % 8);
    out.write(reinterpret_cast<const char*>(&v), sizeof v);
  }
}

const std::string kTransfer = "[transfer]\nemission = [[0.0, 0.0], [8.0, 1.0]]\nextinction = [[0.0, 0.0], [8.0, 0.5]]\n";
const std::string kBox = "[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n";

// A convergence study of one scene file.
std::string study_of(const std::string& scene) {
  return "kind = \"convergence\"\nscene = \"" + scene +
         "\"\n[[method]]\nrule = \"riemann\"\nexpected_order = 1\n[sampling]\nstrategy = \"inviwo\"\n"
         "steps = [0.1, 0.05, 0.025]\n[rays]\ncount = 2\nquick_count = 2\nseed = 1\n";
}

LoadedStudy load(const fs::path& study, double limit) {
  std::ifstream in(study);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return load_study_text(text, study.string(), "s", {.memory_limit = limit});
}

std::string load_error(const fs::path& study, double limit) {
  try {
    load(study, limit);
  } catch (const StudyFileError& e) {
    return e.what();
  }
  return "(no error)";
}

// Before, a study read its scene files' grids and its volumes under no limit but the per-grid
// node cap (1 GiB each): a study of many of them could take many times --max-memory.
TEST(StudyLoader, AScenesFileGridIsSpentFromTheMemoryLimitBeforeItIsBuilt) {
  const fs::path dir = scratch();
  write(dir / "grid.toml", kBox + "[field]\nkind = \"grid\"\nresolution = [64, 64, 64]\n[field.source]\n"
                                  "kind = \"marschner_lobb\"\n" + kTransfer);
  write(dir / "study.toml", study_of("grid.toml"));
  const std::string e = load_error(dir / "study.toml", 1 << 20);  // 1 MiB; the grid takes 2 MiB
  EXPECT_EQ(e, (dir / "study.toml").string() + ": scene: the grid of " + (dir / "grid.toml").string() +
                   " needs 2.0 MiB, more than the 1.0 MiB the study has left under its memory limit (raise it "
                   "with --max-memory GIB)");
  // What was read beyond the estimate counts in the study's memory, which vrv study --all adds up.
  EXPECT_EQ(load(dir / "study.toml", 4 << 20).memory_bytes, 64.0 * 64 * 64 * 8);
  fs::remove_all(dir);
}

TEST(StudyLoader, AVolumeIsReadUnderWhatTheStudyHasLeft) {
  const fs::path dir = scratch();
  write_volume<double>(dir / "v.nrrd", "double");
  write(dir / "volume.toml", kBox + "[field]\nkind = \"volume\"\nfile = \"v.nrrd\"\nplacement = \"box\"\n" + kTransfer);
  write(dir / "study.toml", study_of("volume.toml"));
  const std::string e = load_error(dir / "study.toml", 4096);  // the samples take 5832 bytes
  EXPECT_TRUE(e.starts_with((dir / "study.toml").string() + ": scene: ")) << e;
  EXPECT_NE(e.find("v.nrrd"), std::string::npos) << e;
  EXPECT_NE(e.find("--max-memory"), std::string::npos) << e;
  EXPECT_EQ(load(dir / "study.toml", 1 << 20).memory_bytes, 9.0 * 9 * 9 * 8);
  fs::remove_all(dir);
}

// A 16-bit volume's values are read through a table of every code's value, 512 KiB beside 1458
// bytes of samples: counted before the table is built (it was built first, then refused unnamed).
TEST(StudyLoader, AVolumesTableOfValuesIsCountedBeforeItIsBuilt) {
  const fs::path dir = scratch();
  write_volume<std::int16_t>(dir / "v16.nrrd", "int16");
  write(dir / "volume.toml", kBox + "[field]\nkind = \"volume\"\nfile = \"v16.nrrd\"\nplacement = \"box\"\n" + kTransfer);
  write(dir / "study.toml", study_of("volume.toml"));
  const std::string e = load_error(dir / "study.toml", 100000);
  EXPECT_NE(e.find("v16.nrrd: its samples and their table of values take 525746 bytes, more than the 100000 allowed "
                   "(--max-memory)"), std::string::npos) << e;
  EXPECT_EQ(load(dir / "study.toml", 1 << 20).memory_bytes, 1458.0 + 65536 * 8);
  fs::remove_all(dir);
}

}  // namespace study_loader_test
}  // namespace vrv
