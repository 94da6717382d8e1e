#include "studies/engine/staging.h"

#include <fcntl.h>
#include <stdio.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "studies/engine/interrupt.h"

namespace vrv {
namespace fs = std::filesystem;
namespace {

[[noreturn]] void fail(const fs::path& p, std::string_view what, const std::string& why) {
  throw std::runtime_error(fmt::format("{}: {}: {}", p.string(), what, why));
}

void make_dir(const fs::path& p) {
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec || !fs::is_directory(p)) fail(p, "cannot create the directory", ec ? ec.message() : "not a directory");
}

void remove_tree(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
  if (ec) fail(p, "cannot remove", ec.message());
}

}  // namespace

StudyStaging::StudyStaging(const fs::path& out, const std::string& name, bool resume)
    : out_(out), target_(out / name), staging_(out / ("." + name + ".partial")),
      done_(out / ("." + name + ".done")), lock_(out / ("." + name + ".lock")) {
  make_dir(out_);
  std::error_code ec;
  if (fs::exists(fs::symlink_status(target_, ec)) && !fs::is_directory(target_, ec))
    fail(target_, "cannot write the results", "exists and is not a directory");
  lock_fd_ = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (lock_fd_ < 0) fail(lock_, "cannot open the lock file", std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    fail(target_, "cannot write the results", "another vrv study is writing them (" + lock_.string() + ")");
  }
  remove_tree(done_);  // a previous run killed after publishing, before removing the old results
  resumed_ = resume && fs::is_directory(staging_, ec);
  if (resumed_) {
    remove_temporary_files(staging_, true);
  } else {
    remove_tree(staging_);
    make_dir(staging_);
  }
}

StudyStaging::~StudyStaging() {
  if (lock_fd_ < 0) return;
  ::unlink(lock_.c_str());  // while still holding it; SIGKILL leaves it, unlocked and harmless
  ::close(lock_fd_);        // releases the flock
}

void StudyStaging::publish() {
  const std::lock_guard publishing(publish_mutex());
  std::error_code ec;
  fs::rename(staging_, done_, ec);  // from here on, --resume finds nothing stale to continue
  if (ec) fail(staging_, "cannot publish", ec.message());
  if (fs::is_directory(target_, ec)) {
    if (::renameat2(AT_FDCWD, done_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
      remove_tree(done_);  // the previous run
      return;
    }
    if (errno != EINVAL && errno != ENOSYS) fail(target_, "cannot publish", std::strerror(errno));
    // A file system without the exchange (NFS, some FUSE): two renames.  Killed between them,
    // OUT/NAME is missing for a moment and the previous run is in OUT/.NAME.old.
    const fs::path old = out_ / ("." + target_.filename().string() + ".old");
    remove_tree(old);
    fs::rename(target_, old, ec);
    if (!ec) fs::rename(done_, target_, ec);
    if (ec) fail(target_, "cannot publish", ec.message());
    remove_tree(old);
  } else {
    fs::rename(done_, target_, ec);
    if (ec) fail(target_, "cannot publish", ec.message());
  }
}

}  // namespace vrv
