#pragma once
// Every study measures against the reference.  A reference value that missed its tolerance (the
// work cap reached, an estimate above tol, a non-finite value) would make a table wrong without a
// word, so drivers compute their truths through audited_reference(), which counts the rays and the
// misses, and the study runner adds one check to every study:
//   reference_within_tolerance   value: truths that missed, bound 0 (kind derived)
// The counters are process-wide (the runner runs one study at a time).  Under MPI ranks each rank
// counts the truths of the blocks it was dealt, and rank 0 also those every rank computes
// (lib/util/ranks.h, counts_on_this_rank), so the counts summed over the ranks are one process's.
//
// --resume: checkpoints keep values, not verdicts, so the verdicts are kept beside them.  Before
// each checkpoint is written, the counters as they stand are written (atomically) to
// reference_audit.snapshot in the checkpoints folder, and a resumed run starts its counters from
// the last snapshot.  A truth is recorded before the checkpoint holding it is stored, and the
// snapshots are taken and written one at a time, so the last snapshot counts every truth of every
// stored checkpoint: no miss a resumed run reuses is lost, even when the process was killed
// between a snapshot and its checkpoint.  The counts of a resumed run are an upper bound: a truth
// recorded before the interruption whose checkpoint was not stored (one in flight, or one a study
// recomputes on every run instead of storing it) is counted again when it is recomputed.  The
// verdict is the same as an uninterrupted run's (a truth is deterministic: it misses in both runs
// or in neither).
#include <optional>
#include <string>
#include <string_view>

#include "lib/reference_integrator.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/study_driver.h"

namespace vrv {

struct ReferenceAuditCounts {
  long rays = 0;
  long missed = 0;
  double largest_estimate = 0;  // over every audited ray (NaN when one was NaN)
};

// Records one truth.  Thread-safe.
void record_reference(const ReferenceResult& r);

// integrate_reference(...), recorded: the same two forms.
template <class F>
ReferenceResult audited_reference(const F& field, const Box& box, const TransferFunction& tf,
                                  double background, const Ray& ray, const ReferenceOptions& options) {
  ReferenceResult r = integrate_reference(field, box, tf, background, ray, options);
  record_reference(r);
  return r;
}
ReferenceResult audited_reference(const Scene& scene, const Ray& ray, const ReferenceOptions& options);

// Zeroes the counters (the runner, before a study).
void reset_reference_audit();
ReferenceAuditCounts reference_audit_counts();
// The counts of every rank together (collective where loops are shared over ranks, PixelSharing).
ReferenceAuditCounts reference_audit_counts_over_ranks();

// For a run with checkpoints (the runner, before a study): the counters start at zero, or, when
// `resume`, at the snapshot stored with the interrupted run's checkpoints; from now on a snapshot
// is stored before each checkpoint (Checkpoints::before_store).  Throws StudyResumeError (one
// line) when resuming checkpoints that have no snapshot (written by a vrv before the snapshots)
// or an unreadable one: their misses cannot be known.
void start_reference_audit(Checkpoints& checkpoints, bool resume);

// The snapshot file's text: "rays N", "missed N", "largest_estimate X" (a C99 hex float, exact;
// nan and inf as words) and "end" (written last), one a line; and back (nullopt for any other text).
std::string reference_audit_snapshot(const ReferenceAuditCounts& counts);
std::optional<ReferenceAuditCounts> parse_reference_audit_snapshot(std::string_view text);

// The runner's check from the counts.
StudyCheck reference_audit_check(const ReferenceAuditCounts& counts);

}  // namespace vrv
