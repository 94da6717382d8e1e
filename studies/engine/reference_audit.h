#pragma once
// Every study measures against the reference.  A reference value that missed its tolerance (the
// work cap reached, an estimate above tol, a non-finite value) would make a table wrong without a
// word, so drivers compute their truths through audited_reference() (or record() the projections'
// and colour channels' results), which counts the rays and the misses in the run's ReferenceAudit
// (StudyRun::audit), and the study runner adds one check to every study:
//   reference_within_tolerance   value: truths that missed, bound 0 (kind derived)
// Each run owns its counts (no process-wide state: two studies could run side by side).  Under MPI
// ranks each rank counts the truths of the blocks it was dealt, and rank 0 also those every rank
// computes (lib/util/ranks.h, counts_on_this_rank), so the counts summed over the ranks are one
// process's.
//
// --resume: checkpoints keep values, not verdicts, so the verdicts are kept beside them.  Before
// each checkpoint is written, the counts as they stand are written (atomically) to
// reference_audit.snapshot in the checkpoints folder, and a resumed run starts its counts from
// the last snapshot.  A truth is recorded before the checkpoint holding it is stored, and the
// snapshots are taken and written one at a time, so the last snapshot counts every truth of every
// stored checkpoint: no miss a resumed run reuses is lost, even when the process was killed
// between a snapshot and its checkpoint.  The counts of a resumed run are an upper bound: a truth
// recorded before the interruption whose checkpoint was not stored (one in flight, or one a study
// recomputes on every run instead of storing it) is counted again when it is recomputed.  The
// verdict is the same as an uninterrupted run's (a truth is deterministic: it misses in both runs
// or in neither).
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "lib/projection/projection_result.h"
#include "lib/reference_integrator.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/study_driver.h"

namespace vrv {

struct ReferenceAuditCounts {
  long rays = 0;
  long missed = 0;
  double largest_estimate = 0;  // over every audited ray (NaN when one was NaN)
  void add(bool tolerance_met, double error_estimate);
  void add(const ReferenceResult& r) { add(r.tolerance_met, r.error_estimate); }
  void add(const ProjectionResult& r) { add(r.tolerance_met, r.error_estimate); }
  void add(const ReferenceAuditCounts& more);
};

// One run's counts.  record() is thread-safe.
class ReferenceAudit {
 public:
  ReferenceAudit() = default;
  ReferenceAudit(const ReferenceAudit&) = delete;  // a checkpoint hook may hold its address
  ReferenceAudit& operator=(const ReferenceAudit&) = delete;

  void record(const ReferenceResult& r) { record(r.tolerance_met, r.error_estimate); }
  void record(const ProjectionResult& r) { record(r.tolerance_met, r.error_estimate); }
  void record(bool tolerance_met, double error_estimate);
  // Truths a study counted itself (from values every rank holds): counted once, on rank 0.
  void record(const ReferenceAuditCounts& counts);
  ReferenceAuditCounts counts() const;
  // The counts of every rank together (collective where loops are shared over ranks, PixelSharing).
  ReferenceAuditCounts counts_over_ranks() const;

  // For a run with checkpoints (the runner, before a study): the counts start at zero, or, when
  // `resume`, at the snapshot stored with the interrupted run's checkpoints; from now on a
  // snapshot is stored before each checkpoint (Checkpoints::before_store), so the audit must
  // outlive the checkpoints' stores.  Throws StudyResumeError (one line) when resuming
  // checkpoints that have no snapshot (written by a vrv before the snapshots) or an unreadable
  // one: their misses cannot be known.
  void start(Checkpoints& checkpoints, bool resume);

 private:
  void store_snapshot(const std::filesystem::path& dir);
  mutable std::mutex mutex_;
  ReferenceAuditCounts counts_;
  // Taken while a snapshot is read from the counts and written: snapshots reach the file in the
  // order they were taken, so the file never goes back to fewer truths than a stored checkpoint's.
  std::mutex snapshot_mutex_;
};

// integrate_reference(...), recorded in `audit`: the same two forms.
template <class F>
ReferenceResult audited_reference(ReferenceAudit& audit, const F& field, const Box& box, const TransferFunction& tf,
                                  double background, const Ray& ray, const ReferenceOptions& options) {
  ReferenceResult r = integrate_reference(field, box, tf, background, ray, options);
  audit.record(r);
  return r;
}
ReferenceResult audited_reference(ReferenceAudit& audit, const Scene& scene, const Ray& ray,
                                  const ReferenceOptions& options);

// The snapshot file's text: "rays N", "missed N", "largest_estimate X" (a C99 hex float, exact;
// nan and inf as words) and "end" (written last), one a line; and back (nullopt for any other text).
std::string reference_audit_snapshot(const ReferenceAuditCounts& counts);
std::optional<ReferenceAuditCounts> parse_reference_audit_snapshot(std::string_view text);

// The runner's check from the counts.
StudyCheck reference_audit_check(const ReferenceAuditCounts& counts);

}  // namespace vrv
