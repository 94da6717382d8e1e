#pragma once
// A study's results appear whole or not at all.  The run writes into a staging folder beside the
// results, OUT/.NAME.partial/, and publishes it in one step when everything (tables, checks,
// plots, meta.json) is written: the staging folder is renamed to OUT/.NAME.done and exchanged
// with OUT/NAME (renameat2 RENAME_EXCHANGE, atomic), and the previous run, now at .NAME.done, is
// removed.  At every instant OUT/NAME holds one complete run or the previous one, even under
// SIGKILL.  A lock file (OUT/.NAME.lock, flock) keeps two vrv processes out of one study folder.
//
// The staging folder outlives an interruption: it holds the finished configurations' checkpoints
// (checkpoint.h), which `vrv study NAME --resume` continues from.  Without --resume it is emptied.
#include <filesystem>
#include <string>

namespace vrv {

class StudyStaging {
 public:
  // Takes the lock (throws std::runtime_error naming the folder if another process holds it),
  // removes a stale OUT/.NAME.done, and prepares the staging folder: emptied unless `resume`,
  // else only its stale temporary files are removed.  Throws std::runtime_error (one line) when a
  // folder cannot be created, or when OUT/NAME exists and is not a folder.
  StudyStaging(const std::filesystem::path& out, const std::string& name, bool resume);
  ~StudyStaging();  // releases the lock; the staging folder stays (for --resume) unless published
  StudyStaging(const StudyStaging&) = delete;
  StudyStaging& operator=(const StudyStaging&) = delete;

  const std::filesystem::path& dir() const { return staging_; }     // where the run writes
  const std::filesystem::path& target() const { return target_; }   // OUT/NAME
  bool resumed() const { return resumed_; }  // --resume found a staging folder to continue

  // Replaces OUT/NAME by the staging folder in one step (holding publish_mutex()).
  void publish();

 private:
  std::filesystem::path out_, target_, staging_, done_, lock_;
  int lock_fd_ = -1;
  bool resumed_ = false;
};

}  // namespace vrv
