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
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "lib/image_loop.h"

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
  // distinct keys.  A stored file carries its count and a checksum (CRC-64): one that fails them,
  // or holds other than `expected` values (when given), is refused with StudyResumeError naming
  // the file, never used.
  std::vector<double> get(const std::string& key, const std::function<std::vector<double>()>& compute,
                          std::optional<std::size_t> expected = std::nullopt);

  // Every key from now on is `prefix` + key: a study of an RGB scene runs its kind's study once per
  // channel (channel_study.h), whose keys would otherwise collide.  Not while a get() runs.
  void set_key_prefix(std::string prefix) { key_prefix_ = std::move(prefix); }

  long reused() const { return reused_; }    // configurations taken from the interrupted run
  long computed() const { return computed_; }

  // Called with this folder before each checkpoint is written (from the storing thread; stores
  // are concurrent, so the hook serialises itself): what the run's verdict needs beyond the
  // values (the reference audit's counts, reference_audit.h) is stored first, so that no stored
  // checkpoint goes without it, even when the process is killed between the two writes.
  void before_store(std::function<void(const std::filesystem::path& dir)> hook) { before_store_ = std::move(hook); }
  const std::filesystem::path& dir() const { return dir_; }
  // The resumed run's folder held at least one checkpoint when this run began.
  bool found_stored() const { return found_stored_; }
  // The first value reused from the interrupted run that is not finite, as "FILE: value N is nan"
  // (empty if none): NaN is stored as computed, so when the study then refuses a NaN (a table
  // column without allow_missing) the refusal can name the checkpoint it came from.
  std::string reused_non_finite() const;

 private:
  std::filesystem::path file(const std::string& key) const;
  std::optional<std::vector<double>> find(const std::string& key) const;
  void store(const std::string& key, const std::vector<double>& values);
  void note_non_finite(const std::string& key, const std::vector<double>& values);

  std::filesystem::path dir_;
  std::string key_prefix_;
  std::function<void(const std::filesystem::path&)> before_store_;
  bool found_stored_ = false;
  mutable std::mutex reused_non_finite_mutex_;
  std::string reused_non_finite_;
  std::atomic<long> reused_{0}, computed_{0};
  long kill_after_ = 0;  // test hook: VRV_TEST_KILL_AFTER_CHECKPOINTS=N[:SIGNAL]
  int kill_signal_ = 9;
};

// What a study's computation takes: the `expected` values stored under `key`, or compute() stored
// under it.  Empty: compute every time (tests, or a run without checkpoints).
using StudyCheckpoint = std::function<std::vector<double>(
    const std::string& key, std::size_t expected, const std::function<std::vector<double>()>& compute)>;
StudyCheckpoint checkpoint_function(Checkpoints* checkpoints);  // empty for null
// Through `checkpoint`, or compute() when it is empty.
std::vector<double> checkpointed(const StudyCheckpoint& checkpoint, const std::string& key, std::size_t expected,
                                 const std::function<std::vector<double>()>& compute);

// The stored checkpoints, or none: what a driver's run sees (StudyRun::checkpoints may be null).
// `expected`, when given: the count of values a stored checkpoint must hold.
std::vector<double> checkpointed(Checkpoints* checkpoints, const std::string& key,
                                 const std::function<std::vector<double>()>& compute,
                                 std::optional<std::size_t> expected = std::nullopt);

// A long loop (pixels, rays, views) checkpointed in blocks: items 0..n-1 of `width` doubles each,
// item(i, out) filling out[0..width); blocks of `block` consecutive items are computed in parallel
// (and the items inside a block too) and each is stored as one checkpoint, `key`.<first item>, so
// an interrupted loop resumes at the first missing block.  `advance` (may be empty) is called once
// per item, computed or reused.  Returns the n * width values, item-major.
std::vector<double> checkpointed_items(Checkpoints* checkpoints, const std::string& key, long n, long block,
                                       std::size_t width, const std::function<void(long, std::span<double>)>& item,
                                       const std::function<void(long)>& advance = {});

// image_records' blocks (lib/image_loop.h), each stored as one checkpoint, `key`.<first
// position>, and restored from there on --resume: checkpointed_items for a loop over a camera's
// pixels (hooks.block: one image row).  Empty for null checkpoints.
BlockStore checkpoint_blocks(Checkpoints* checkpoints, const std::string& key);

// The whole vector of records of one configuration as one checkpoint: encode(record) appends its
// doubles, decode(values, i) rebuilds record i from `width` doubles at values[i * width].
// `count`, when given: the number of records a stored checkpoint must hold.
template <class T, class Compute, class Encode, class Decode>
std::vector<T> checkpointed_records(Checkpoints* checkpoints, const std::string& key, std::size_t width,
                                    Compute&& compute, Encode&& encode, Decode&& decode,
                                    std::optional<std::size_t> count = std::nullopt) {
  std::vector<T> computed;
  bool fresh = false;
  const std::vector<double> v = checkpointed(checkpoints, key, [&] {
    computed = compute();
    fresh = true;
    std::vector<double> flat;
    flat.reserve(computed.size() * width);
    for (const T& r : computed) encode(r, flat);
    return flat;
  }, count ? std::optional(*count * width) : std::nullopt);
  if (fresh) return computed;
  if (width == 0 || v.size() % width != 0)
    throw StudyResumeError("checkpoint " + key + ": " + std::to_string(v.size()) + " values, not records of " +
                           std::to_string(width));
  std::vector<T> out;
  for (std::size_t i = 0; i + width <= v.size(); i += width) out.push_back(decode(std::span<const double>(v).subspan(i, width)));
  return out;
}

}  // namespace vrv
