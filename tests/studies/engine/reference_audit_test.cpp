#include "studies/engine/reference_audit.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "lib/io/atomic_file.h"
#include "lib/scene_file.h"

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
  ReferenceAudit audit;
  const Scene scene = marschner_lobb(6);
  const ReferenceResult r = audited_reference(audit, scene, make_ray({-3, 0.1, 0.2}, {1, 0, 0}), {1e-12});
  ASSERT_TRUE(r.tolerance_met);
  const ReferenceAuditCounts c = audit.counts();
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
  ReferenceAudit audit;
  const ReferenceResult r =
      audited_reference(audit, marschner_lobb(1e6), make_ray({-3, 0.1, 0.2}, {1, 0, 0.01}), {1e-12});
  ASSERT_FALSE(r.tolerance_met);
  audited_reference(audit, marschner_lobb(6), make_ray({-3, 0.1, 0.2}, {1, 0, 0}), {1e-12});
  const ReferenceAuditCounts c = audit.counts();
  EXPECT_EQ(c.rays, 2);
  EXPECT_EQ(c.missed, 1);
  EXPECT_GE(c.largest_estimate, r.error_estimate);
  const StudyCheck check = reference_audit_check(c);
  EXPECT_FALSE(check.pass);
  EXPECT_EQ(check.value, 1);
}

// Each run has its own counts: a miss in one is not seen by another (two studies may run side by
// side in one process); a projection's or a channel's result is counted like a ray's.
TEST(ReferenceAudit, EachRunCountsItsOwnTruths) {
  ReferenceAudit first, second;
  audited_reference(first, marschner_lobb(1e6), make_ray({-3, 0.1, 0.2}, {1, 0, 0.01}), {1e-12});
  ProjectionResult projection;
  projection.error_estimate = 2e-13;
  second.record(projection);
  projection.tolerance_met = false;
  projection.error_estimate = std::numeric_limits<double>::quiet_NaN();
  second.record(projection);
  second.record(true, 1e-14);
  EXPECT_EQ(first.counts().rays, 1);
  EXPECT_EQ(first.counts().missed, 1);
  EXPECT_EQ(second.counts().rays, 3);
  EXPECT_EQ(second.counts().missed, 1);
  EXPECT_TRUE(std::isnan(second.counts().largest_estimate));  // a NaN estimate is kept, not lost in a max
}

TEST(ReferenceAudit, SnapshotRoundTripsExactlyNaNAndInfinityIncluded) {
  const double inf = std::numeric_limits<double>::infinity();
  for (const double estimate : {0.0, 4.1541867837243e-14, std::nextafter(1e-16, 1.0),
                                std::numeric_limits<double>::denorm_min(), inf}) {
    const ReferenceAuditCounts c{123456789012L, 42, estimate};
    const auto back = parse_reference_audit_snapshot(reference_audit_snapshot(c));
    ASSERT_TRUE(back) << reference_audit_snapshot(c);
    EXPECT_EQ(back->rays, c.rays);
    EXPECT_EQ(back->missed, c.missed);
    EXPECT_EQ(back->largest_estimate, c.largest_estimate);  // bit for bit
  }
  const auto nan = parse_reference_audit_snapshot(
      reference_audit_snapshot({3, 1, std::numeric_limits<double>::quiet_NaN()}));
  ASSERT_TRUE(nan);
  EXPECT_EQ(nan->missed, 1);
  EXPECT_TRUE(std::isnan(nan->largest_estimate));
}

TEST(ReferenceAudit, AnythingButAWholeSnapshotIsRefused) {
  const std::string good = reference_audit_snapshot({5, 2, 0x1p-40});
  ASSERT_TRUE(parse_reference_audit_snapshot(good));
  for (const std::string& bad : {std::string(), good.substr(0, good.size() - 4),  // no "end"
                                good + "rays 1\n", std::string("rays 5\nmissed 6\nlargest_estimate 0\nend\n"),
                                std::string("rays -1\nmissed 0\nlargest_estimate 0\nend\n"),
                                std::string("rays 5\nmissed 2x\nlargest_estimate 0\nend\n"),
                                std::string("rays 5\nmissed 2\nlargest_estimate 0x1q\nend\n"),
                                std::string("missed 2\nrays 5\nlargest_estimate 0\nend\n")})
    EXPECT_FALSE(parse_reference_audit_snapshot(bad)) << bad;
}

// A miss recorded before a checkpoint is stored is still counted by a run resuming that checkpoint
// (which reuses the value and computes no truth); checkpoints without a snapshot are refused.
TEST(ReferenceAudit, AResumedRunStartsFromTheCountsStoredWithItsCheckpoints) {
  const std::filesystem::path dir = std::filesystem::path(VRV_BINARY_DIR) / "test_reference_audit_resume" /
                                    std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  ReferenceAuditCounts before;
  {
    ReferenceAudit audit;
    Checkpoints first(dir, "study", false);
    audit.start(first, false);
    first.get("truth", [&] {
      const ReferenceResult r =
          audited_reference(audit, marschner_lobb(1e6), make_ray({-3, 0.1, 0.2}, {1, 0, 0.01}), {1e-12});
      return std::vector<double>{r.value};
    });
    before = audit.counts();
  }  // the run that stored the checkpoint is gone
  ASSERT_EQ(before.rays, 1);
  ASSERT_EQ(before.missed, 1);
  {
    ReferenceAudit audit;
    Checkpoints resumed(dir, "study", true);
    audit.start(resumed, true);
    bool computed = false;
    resumed.get("truth", [&] {
      computed = true;
      return std::vector<double>{0};
    });
    EXPECT_FALSE(computed);
    const ReferenceAuditCounts after = audit.counts();
    EXPECT_EQ(after.rays, before.rays);
    EXPECT_EQ(after.missed, before.missed);
    EXPECT_EQ(after.largest_estimate, before.largest_estimate);
    EXPECT_FALSE(reference_audit_check(after).pass);
  }
  // A fresh run (not resuming) starts at zero whatever the folder holds.
  {
    ReferenceAudit audit;
    Checkpoints fresh(dir, "study", false);
    audit.start(fresh, false);
    EXPECT_EQ(audit.counts().rays, 0);
  }
  std::filesystem::remove(dir / "reference_audit.snapshot");
  {
    ReferenceAudit audit;
    Checkpoints old(dir, "study", true);
    EXPECT_THROW(audit.start(old, true), StudyResumeError);
  }
  write_file_atomically(dir / "reference_audit.snapshot", "rays 1\nmissed 1\n");
  {
    ReferenceAudit audit;
    Checkpoints torn(dir, "study", true);
    EXPECT_THROW(audit.start(torn, true), StudyResumeError);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace vrv
