#include "lib/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <thread>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

#include <fmt/format.h>

namespace vrv {
namespace {

[[noreturn]] void write_failure(const std::filesystem::path& path, const std::string& reason) {
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

// A test hook, so that "interrupted mid-write" is deterministic (tests/studies/cli): with
// VRV_TEST_SIGNAL_AT_WRITE=N[:SIGNAL], the N-th file written sends this process SIGNAL (SIGINT by
// default) while its temporary exists, and the next write waits for the signal to stop the process.
std::atomic<bool> g_test_signal_sent{false};

void test_signal_at_write() {
  static std::atomic<long> writes{0};
  const char* hook = std::getenv("VRV_TEST_SIGNAL_AT_WRITE");
  if (!hook) return;
  char* rest = nullptr;
  const long n = std::strtol(hook, &rest, 10);
  const int sig = *rest == ':' ? std::atoi(rest + 1) : SIGINT;
  if (++writes == n) {
    g_test_signal_sent = true;
    ::kill(::getpid(), sig);  // to the process: a thread that waits for signals takes it
  }
}

void test_wait_for_signal() {
  if (g_test_signal_sent) std::this_thread::sleep_for(std::chrono::seconds(30));
}

}  // namespace

std::string temporary_suffix() {
  // The pid keeps the stale sweep working (studies/engine/interrupt.h); the random part keeps
  // names apart where pids are not: threads of one process, and processes of other machines
  // writing into a shared folder (a reference cache on a cluster's file system).
  thread_local std::mt19937_64 bits{(static_cast<std::uint64_t>(std::random_device{}()) << 32) ^
                                    std::random_device{}()};
  return fmt::format(".tmp.{}.{:016x}", ::getpid(), bits());
}

std::shared_mutex& temporary_files_mutex() {
  static std::shared_mutex m;
  return m;
}

void write_file_atomically(const std::filesystem::path& path, std::string_view contents) {
  if (path.empty() || !path.has_filename()) write_failure(path, "not a file name");
  test_wait_for_signal();
  const std::shared_lock temporaries(temporary_files_mutex());
  std::filesystem::path tmp = path;
  tmp += temporary_suffix();

  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) write_failure(path, errno_reason(errno));

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
    write_failure(path, errno_reason(err));
  }
  test_signal_at_write();

  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    ::unlink(tmp.c_str());
    write_failure(path, ec.message());
  }
  sync_directory(path.parent_path());
}

}  // namespace vrv
