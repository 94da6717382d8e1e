#include "studies/cli/published_folder.h"

#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "lib/io/output_paths.h"
#include "studies/engine/interrupt.h"

namespace vrv::cli {

namespace fs = std::filesystem;

namespace {

// OUT/NAME from `dir` as given ("o", "o/", "a/../o", "."): the staging folder and the lock are
// NAME's siblings, so NAME must be a real name.
fs::path folder_path(const fs::path& dir, const std::string& option) {
  std::error_code ec;
  fs::path p = fs::absolute(dir, ec).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();
  if (ec || p == p.root_path() || !p.has_filename())
    throw std::invalid_argument(fmt::format("{}: {}: cannot be an output folder", option, dir.string()));
  return p;
}

}  // namespace

PublishedFolder::PublishedFolder(const fs::path& dir, const std::string& marker, const std::string& option)
    : option_(option) {
  check_replaceable_dir(dir, marker, option);
  const fs::path target = folder_path(dir, option);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(target, ec))) created_ = target;
  check_writable_dir(dir, option);  // names `dir` as given when it, or its parent, cannot be made
  try {
    staging_.emplace(target.parent_path(), target.filename().string(), false);
  } catch (const std::runtime_error& e) {  // the lock held by another vrv, an unwritable parent
    remove_created();
    throw std::invalid_argument(fmt::format("{}: {}", option, e.what()));
  }
  set_interrupt_cleanup_dir(staging_->dir());
}

PublishedFolder::~PublishedFolder() {
  set_interrupt_cleanup_dir({});
  if (!published_) {
    std::error_code ec;
    fs::remove_all(staging_->dir(), ec);  // nothing to resume: a verify or export reruns whole
    staging_.reset();                     // its lock released before the folder goes
    remove_created();
  }
}

void PublishedFolder::remove_created() {
  std::error_code ec;
  if (!created_.empty()) fs::remove(created_, ec);  // only while still empty: never another's files
}

void PublishedFolder::write_and_publish(const std::function<void(const fs::path& staging)>& write) {
  try {
    write(staging_->dir());
    staging_->publish();
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("{}: {}: not written, the previous outputs are unchanged: {}", option_,
                                         target().string(), e.what()));
  }
  published_ = true;
}

}  // namespace vrv::cli
