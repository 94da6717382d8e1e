#pragma once
// A progress bar on stderr for long jobs (renders, studies, gates): rate and time left.
// Silent when disabled, when stderr is not a terminal, or for jobs shorter than a second,
// so stdout stays machine-readable and logs stay clean.  Safe to call from many threads.
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace vrv {

class Progress {
 public:
  // enabled = false (--quiet) silences it; otherwise it draws only on a terminal.
  Progress(std::string label, long total, bool enabled);
  ~Progress();
  void advance(long done = 1);  // thread-safe; redraws at most every 0.2 s
  void finish();                // clears the line

 private:
  void draw(long done);
  std::string label_;
  long total_;
  bool active_;
  std::atomic<long> done_{0};
  std::mutex draw_mutex_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
};

}  // namespace vrv
