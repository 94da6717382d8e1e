#pragma once
// Checkpoints of a long study: each finished configuration's numbers are stored in the staging
// folder (staging.h) as they come, so that `vrv study NAME --resume` after an interruption
// computes only what is missing.  Values are stored exactly (C99 hex floats, NaN and inf
// included), so a resumed run's tables are byte-identical to an uninterrupted run's.
//
// A checkpoint belongs to one study file text and one variant (--quick or not): resuming with a
// changed file or the other variant is refused (Checkpoints throws StudyResumeError).
#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vrv {

class StudyResumeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Checkpoints {
 public:
  // `dir` is the staging folder's checkpoints/ (created).  `identity` names what the numbers
  // depend on (the study file text and the variant); resuming checks it, a fresh run records it.
  Checkpoints(const std::filesystem::path& dir, std::string_view identity, bool resume);

  // The values stored under `key` (letters, digits, '_', '-', '.') by this run or the one being
  // resumed; else computes them, stores them (atomically) and returns them.  Thread-safe for
  // distinct keys.
  std::vector<double> get(const std::string& key, const std::function<std::vector<double>()>& compute);

  long reused() const { return reused_; }    // configurations taken from the interrupted run
  long computed() const { return computed_; }

 private:
  std::optional<std::vector<double>> find(const std::string& key) const;
  void store(const std::string& key, const std::vector<double>& values);

  std::filesystem::path dir_;
  std::atomic<long> reused_{0}, computed_{0};
  long kill_after_ = 0;  // test hook: VRV_TEST_KILL_AFTER_CHECKPOINTS=N[:SIGNAL]
  int kill_signal_ = 9;
};

// What a study's computation takes: the values stored under `key`, or compute() stored under it.
// Empty: compute every time (tests, or a run without checkpoints).
using StudyCheckpoint = std::function<std::vector<double>(const std::string& key,
                                                          const std::function<std::vector<double>()>& compute)>;
StudyCheckpoint checkpoint_function(Checkpoints* checkpoints);  // empty for null

// The stored checkpoints, or none: what a driver's run sees (StudyRun::checkpoints may be null).
std::vector<double> checkpointed(Checkpoints* checkpoints, const std::string& key,
                                 const std::function<std::vector<double>()>& compute);

}  // namespace vrv
