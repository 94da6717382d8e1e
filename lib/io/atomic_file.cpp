#include "lib/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

#include <fmt/format.h>

namespace vrv {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& reason) {
  throw std::runtime_error(fmt::format("{}: cannot write: {}", path.string(), reason));
}

std::string errno_reason(int err) { return std::strerror(err); }

// Writes everything to fd, retrying short writes and interrupted calls; returns 0 or an errno value.
int write_all(int fd, std::string_view data) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd, data.data(), data.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    data.remove_prefix(static_cast<std::size_t>(n));
  }
  return 0;
}

// Best effort: makes the rename itself durable.  A failure here does not undo a completed write.
void sync_directory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view contents) {
  if (path.empty() || !path.has_filename()) fail(path, "not a file name");
  std::filesystem::path tmp = path;
  tmp += fmt::format(".tmp.{}", ::getpid());

  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail(path, errno_reason(errno));

  int err = write_all(fd, contents);
  if (err == 0) {
    while (::fsync(fd) != 0) {
      if (errno != EINTR) {
        err = errno;
        break;
      }
    }
  }
  // close can report a deferred write error (NFS, quota); it must not be ignored.
  if (::close(fd) != 0 && err == 0 && errno != EINTR) err = errno;
  if (err != 0) {
    ::unlink(tmp.c_str());
    fail(path, errno_reason(err));
  }

  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    ::unlink(tmp.c_str());
    fail(path, ec.message());
  }
  sync_directory(path.parent_path());
}

}  // namespace vrv
