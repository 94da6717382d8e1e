#include "lib/util/progress.h"

#include <unistd.h>

#include <cstdio>

#include <fmt/format.h>

namespace vrv {

Progress::Progress(std::string label, long total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      active_(enabled && total > 0 && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() { finish(); }

void Progress::advance(long done) {
  const long now_done = done_.fetch_add(done) + done;
  if (!active_) return;
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;  // another thread is drawing: skip, never wait
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < std::chrono::seconds(1) || now - last_draw_ < std::chrono::milliseconds(200)) return;
  last_draw_ = now;
  draw(now_done);
}

void Progress::draw(long done) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = done / elapsed;
  const double left = rate > 0 ? (total_ - done) / rate : 0;
  constexpr int width = 30;
  const int filled = static_cast<int>(width * static_cast<double>(done) / total_);
  fmt::print(stderr, "\r{} [{}{}] {}/{}  {:.3g}/s  {:.0f} s left ", label_, std::string(filled, '#'),
             std::string(width - filled, ' '), done, total_, rate, left);
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::finish() {
  std::lock_guard lock(draw_mutex_);
  if (drawn_) fmt::print(stderr, "\r\033[K");
  drawn_ = false;
}

}  // namespace vrv
