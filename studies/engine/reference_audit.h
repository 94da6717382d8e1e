#pragma once
// Every study measures against the reference.  A reference value that missed its tolerance (the
// work cap reached, an estimate above tol, a non-finite value) would make a table wrong without a
// word, so drivers compute their truths through audited_reference(), which counts the rays and the
// misses, and the study runner adds one check to every study:
//   reference_within_tolerance   value: truths that missed, bound 0 (kind derived)
// The counters are process-wide (the runner runs one study at a time).  A truth restored from a
// checkpoint by --resume is not audited again (checkpoints keep values, not verdicts): a resumed
// run audits the truths it computes.
#include "lib/reference_integrator.h"
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

// The runner's check from the counts.
StudyCheck reference_audit_check(const ReferenceAuditCounts& counts);

}  // namespace vrv
