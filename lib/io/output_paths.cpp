#include "lib/io/output_paths.h"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"

namespace vrv {

namespace fs = std::filesystem;

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

void check_inputs_outside(const fs::path& dir, const std::vector<fs::path>& inputs, std::string_view option) {
  std::error_code ec;
  for (const fs::path& input : inputs) {
    if (input.empty()) continue;
    for (fs::path p = fs::absolute(input, ec).parent_path(); !p.empty(); p = p.parent_path()) {
      if (same_file(p, dir))
        throw std::invalid_argument(fmt::format(
            "{}: {}: holds the input {}, which the outputs written there could replace; choose another {}",
            option, dir.string(), input.string(), option));
      if (p == p.root_path()) break;
    }
  }
}

void check_writable_dir(const fs::path& dir, std::string_view option) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir, ec))
    throw std::invalid_argument(fmt::format("{}: {}: cannot create the folder{}", option, dir.string(),
                                            ec ? ": " + ec.message() : std::string(" (a file is in the way)")));
  const fs::path probe = dir / (".vrv-probe" + temporary_suffix());
  if (!std::ofstream(probe))
    throw std::invalid_argument(fmt::format("{}: {}: cannot write into it", option, dir.string()));
  fs::remove(probe, ec);
}

void check_replaceable_dir(const fs::path& dir, std::string_view marker, std::string_view option) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec))) return;
  if (!fs::is_directory(dir, ec))
    throw std::invalid_argument(fmt::format("{}: {}: exists and is not a directory", option, dir.string()));
  if (fs::is_empty(dir, ec) || fs::exists(dir / marker, ec)) return;
  throw std::invalid_argument(fmt::format(
      "{}: {}: holds files vrv did not write (no {}), and a run replaces the whole folder; give a new or "
      "empty folder, or one an earlier run wrote",
      option, dir.string(), marker));
}

}  // namespace vrv
