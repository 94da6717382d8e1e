#include "studies/engine/reference_audit.h"

#include <cmath>
#include <mutex>

namespace vrv {
namespace {

std::mutex audit_mutex;
ReferenceAuditCounts audit;

}  // namespace

void record_reference(const ReferenceResult& r) {
  const std::lock_guard lock(audit_mutex);
  ++audit.rays;
  if (!r.tolerance_met) ++audit.missed;
  if (std::isnan(r.error_estimate) || r.error_estimate > audit.largest_estimate)
    audit.largest_estimate = r.error_estimate;
}

ReferenceResult audited_reference(const Scene& scene, const Ray& ray, const ReferenceOptions& options) {
  ReferenceResult r = integrate_reference(scene, ray, options);
  record_reference(r);
  return r;
}

void reset_reference_audit() {
  const std::lock_guard lock(audit_mutex);
  audit = {};
}

ReferenceAuditCounts reference_audit_counts() {
  const std::lock_guard lock(audit_mutex);
  return audit;
}

StudyCheck reference_audit_check(const ReferenceAuditCounts& counts) {
  StudyCheck c;
  c.name = "reference_within_tolerance";
  c.value = static_cast<double>(counts.missed);
  c.bound = 0;
  c.pass = counts.missed == 0;
  c.kind = CheckKind::derived;
  // The detail is the same for a resumed run (--resume computes only part of the truths, and its
  // tables must match an uninterrupted run's byte for byte): the counts go to meta.json.
  c.detail = "reference truths that missed their tolerance (work cap, estimate above tol or not finite)";
  return c;
}

}  // namespace vrv
