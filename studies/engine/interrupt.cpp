#include "studies/engine/interrupt.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <string>
#include <system_error>
#include <thread>

#include "lib/io/atomic_file.h"

namespace vrv {
namespace {

std::mutex g_state;  // guards the two below
std::filesystem::path g_cleanup_dir;
std::atomic<pid_t> g_child{0};

sigset_t stop_signals() {
  sigset_t s;
  sigemptyset(&s);
  sigaddset(&s, SIGINT);
  sigaddset(&s, SIGTERM);
  return s;
}

// "name.tmp.<pid>" or "name.tmp.<pid>.<ext>" (the plot script's): the pid, else 0.
pid_t temporary_pid(const std::string& name) {
  const auto at = name.rfind(".tmp.");
  if (at == std::string::npos) return 0;
  const std::string rest = name.substr(at + 5);
  std::size_t used = 0;
  long pid = 0;
  try {
    pid = std::stol(rest, &used);
  } catch (const std::exception&) {
    return 0;
  }
  if (used != rest.size() && rest[used] != '.') return 0;
  return pid > 0 ? static_cast<pid_t>(pid) : 0;
}

bool running(pid_t pid) { return ::kill(pid, 0) == 0 || errno == EPERM; }

[[noreturn]] void stop(int sig) {
  const std::lock_guard publishing(publish_mutex());  // never half way through publishing
  if (const pid_t child = g_child.load(); child > 0) ::kill(-child, SIGTERM);
  temporary_files_mutex().lock();  // never unlocked: no temporary is created after the sweep
  {
    const std::lock_guard lock(g_state);
    if (!g_cleanup_dir.empty()) remove_temporary_files(g_cleanup_dir, false);
  }
  std::fprintf(stderr, "vrv: stopped by signal %d; published results are unchanged\n", sig);
  std::fflush(stderr);
  ::_exit(128 + sig);
}

std::thread g_watcher;
sigset_t g_old_mask;
struct sigaction g_old_int, g_old_term;
std::atomic<bool> g_shutdown{false};

}  // namespace

std::mutex& publish_mutex() {
  static std::mutex m;
  return m;
}

void set_interrupt_cleanup_dir(const std::filesystem::path& dir) {
  const std::lock_guard lock(g_state);
  g_cleanup_dir = dir;
}

void set_interrupt_child(pid_t pid) { g_child = pid; }

int remove_temporary_files(const std::filesystem::path& dir, bool only_stale) {
  int removed = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir, ec)) {
    const pid_t pid = temporary_pid(e.path().filename().string());
    if (pid == 0 || !e.is_regular_file(ec)) continue;
    const bool mine = pid == ::getpid();
    if (only_stale ? (!mine && !running(pid)) : mine) removed += std::filesystem::remove(e.path(), ec) ? 1 : 0;
  }
  return removed;
}

void unblock_stop_signals() {
  const sigset_t s = stop_signals();
  pthread_sigmask(SIG_UNBLOCK, &s, nullptr);
}

InterruptGuard::InterruptGuard() {
  g_shutdown = false;
  const sigset_t s = stop_signals();
  pthread_sigmask(SIG_BLOCK, &s, &g_old_mask);
  // A shell starts background jobs with SIGINT ignored; an ignored signal may be dropped before
  // sigwait sees it, so the disposition goes back to the default (never acted on: blocked).
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigaction(SIGINT, &dfl, &g_old_int);
  sigaction(SIGTERM, &dfl, &g_old_term);
  g_watcher = std::thread([s] {
    int sig = 0;
    while (sigwait(&s, &sig) == 0)
      if (g_shutdown) return;  // the guard's own wake-up
      else stop(sig);
  });
}

InterruptGuard::~InterruptGuard() {
  // Wake the watcher with a signal aimed at it alone; it sees the flag and returns.
  g_shutdown = true;
  pthread_kill(g_watcher.native_handle(), SIGTERM);
  g_watcher.join();
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
  pthread_sigmask(SIG_SETMASK, &g_old_mask, nullptr);
}

}  // namespace vrv
