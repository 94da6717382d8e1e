#pragma once
// An output folder that a command (vrv verify --out, vrv gate's cases, vrv export --out) publishes
// as one unit, the way a study publishes its results: the run writes into a staging folder beside
// it and replaces the folder whole in one atomic exchange (StudyStaging, studies/engine/staging.h).
// So the folder holds the previous run or the new one, never a mix: no file of an earlier run stays
// beside a new run's (an earlier bounds.csv or error image), and an interruption, a full disk or an
// error leaves the previous outputs whole.  A lock on the folder refuses a second vrv writing it.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "studies/engine/staging.h"

namespace vrv::cli {

class PublishedFolder {
 public:
  // Before any work: `dir` can be replaced (missing, empty or holding `marker`, the file every run
  // writes: check_replaceable_dir), its parent can be written, and no other vrv holds its lock.
  // std::invalid_argument "<option>: <dir>: <reason>" (one line) otherwise.  SIGINT and SIGTERM,
  // when an InterruptGuard is in place, remove the staging folder's temporary files.
  PublishedFolder(const std::filesystem::path& dir, const std::string& marker, const std::string& option);
  ~PublishedFolder();  // unpublished (an error): the staging folder is removed
  PublishedFolder(const PublishedFolder&) = delete;
  PublishedFolder& operator=(const PublishedFolder&) = delete;

  const std::filesystem::path& target() const { return staging_->target(); }  // the folder, absolute
  // Runs `write` on the staging folder, then replaces the folder by it in one step.  A failure
  // (a full disk) is one line naming the folder and saying the previous outputs are unchanged.
  void write_and_publish(const std::function<void(const std::filesystem::path& staging)>& write);

 private:
  // The folder checking it created (absolute), removed again, empty, when nothing is published:
  // a refused run leaves no empty folder behind.
  void remove_created();
  std::optional<StudyStaging> staging_;
  std::string option_;
  std::filesystem::path created_;
  bool published_ = false;
};

}  // namespace vrv::cli
