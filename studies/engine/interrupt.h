#pragma once
// SIGINT and SIGTERM during a study: a watcher thread (sigwait) takes them instead of the default
// action, so that vrv stops promptly and tidily whatever the worker threads are doing: it ends the
// child processes it started (the plot script), removes this process's temporary files
// (*.tmp.<pid>) from the folders it was writing, and exits with 128 + the signal (130, 143).  The
// published results are never touched: a study writes into its staging folder and publishes it in
// one rename (staging.h), which the watcher waits for if one is under way.
//
// Signals are blocked in every thread (workers inherit the mask, so create the InterruptGuard
// before any worker thread exists); a background `vrv &` whose shell set SIGINT to ignored still
// stops on Ctrl-C's SIGINT sent by kill, since the disposition no longer matters.
#include <sys/types.h>

#include <filesystem>
#include <mutex>

namespace vrv {

class InterruptGuard {
 public:
  InterruptGuard();   // blocks SIGINT/SIGTERM and starts the watcher
  ~InterruptGuard();  // stops the watcher and restores the signal mask
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
};

// In a forked child before exec: the signal mask survives exec, and a child that cannot be
// stopped by SIGTERM would outlive vrv.
void unblock_stop_signals();

// The folder whose *.tmp.<pid> files an interruption removes (one at a time; empty for none).
void set_interrupt_cleanup_dir(const std::filesystem::path& dir);
// A child process (its own process group) that an interruption ends with SIGTERM; 0 for none.
void set_interrupt_child(pid_t pid);
// Held while results are being published: an interruption waits for it.
std::mutex& publish_mutex();

// Removes *.tmp.<pid> files under `dir` (recursively) whose process is not running, or all of
// this process's own; returns how many were removed.  (A worker thread may still create one
// between this and the exit; the next run's stale sweep removes it.)
int remove_temporary_files(const std::filesystem::path& dir, bool only_stale);

}  // namespace vrv
