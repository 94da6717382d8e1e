#include "studies/engine/reference_audit.h"

#include <gtest/gtest.h>

#include "lib/io/scene_file.h"

namespace vrv {
namespace {

Scene marschner_lobb(double fM) {
  return parse_scene(
      "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
      "[field]\nkind = \"marschner_lobb\"\nfM = " + std::to_string(fM) + "\n"
      "[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 0.5]]\n",
      "audit.toml");
}

TEST(ReferenceAudit, CountsTruthsAndPassesWhenEveryOneMetItsTolerance) {
  reset_reference_audit();
  const Scene scene = marschner_lobb(6);
  const ReferenceResult r = audited_reference(scene, make_ray({-3, 0.1, 0.2}, {1, 0, 0}), {1e-12});
  ASSERT_TRUE(r.tolerance_met);
  const ReferenceAuditCounts c = reference_audit_counts();
  EXPECT_EQ(c.rays, 1);
  EXPECT_EQ(c.missed, 0);
  EXPECT_EQ(c.largest_estimate, r.error_estimate);
  const StudyCheck check = reference_audit_check(c);
  EXPECT_TRUE(check.pass);
  EXPECT_EQ(check.kind, CheckKind::derived);
}

// fM = 1e6: the ray needs more than the work cap, so its truth misses tol and the study's
// check fails (before the audit, the study would have compared against it without a word).
TEST(ReferenceAudit, ATruthThatMissedItsToleranceFailsTheCheck) {
  reset_reference_audit();
  const ReferenceResult r =
      audited_reference(marschner_lobb(1e6), make_ray({-3, 0.1, 0.2}, {1, 0, 0.01}), {1e-12});
  ASSERT_FALSE(r.tolerance_met);
  audited_reference(marschner_lobb(6), make_ray({-3, 0.1, 0.2}, {1, 0, 0}), {1e-12});
  const ReferenceAuditCounts c = reference_audit_counts();
  EXPECT_EQ(c.rays, 2);
  EXPECT_EQ(c.missed, 1);
  EXPECT_GE(c.largest_estimate, r.error_estimate);
  const StudyCheck check = reference_audit_check(c);
  EXPECT_FALSE(check.pass);
  EXPECT_EQ(check.value, 1);
  reset_reference_audit();
  EXPECT_EQ(reference_audit_counts().rays, 0);
}

}  // namespace
}  // namespace vrv
