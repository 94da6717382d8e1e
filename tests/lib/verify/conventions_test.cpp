// lib/verify/conventions: a placement consistent with the expected order is the renderer's
// convention, not a fault; the same placement against a higher expected order is a fault.
#include <cmath>
#include <iostream>
#include <string>

#include <gtest/gtest.h>

#include "lib/verify/conventions.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_toy {
namespace {

VerifyOptions expecting(double order) {
  VerifyOptions o;
  o.expected_order = order;
  return o;
}

// The false alarm of issue 24: samples at the start of each step, verified with the order they
// give (1), passed but were told "fault: half-step offset".
TEST_F(VerifyToy, StartOfStepAtExpectedOrderOneIsAConventionNotAFault) {
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::step_start, "start"), expecting(1));
  EXPECT_TRUE(r.pass) << r.verdict.reason;
  EXPECT_EQ(r.verdict.verdict, Verdict::converges) << r.verdict.reason;
  EXPECT_FALSE(has_fault(r, FaultKind::half_step_offset));
  ASSERT_EQ(r.conventions.size(), 1u);
  EXPECT_EQ(r.conventions[0].kind, FaultKind::half_step_offset);
  EXPECT_EQ(r.conventions[0].behaviour, "samples at the start of each step");
  const auto j = to_json(r);
  EXPECT_EQ(j["conventions"][0]["behaves_like"], "samples at the start of each step");
  EXPECT_EQ(j["expected_order"], 1.0);
}

TEST_F(VerifyToy, StartOfStepAgainstSecondOrderIsAFault) {
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::step_start, "start2"), expecting(2));
  EXPECT_FALSE(r.pass);
  EXPECT_TRUE(has_fault(r, FaultKind::half_step_offset));
  EXPECT_TRUE(r.conventions.empty());
}

TEST_F(VerifyToy, EndOfStepAtExpectedOrderOneIsAConvention) {
  const VerifyReport r = verify_images(scene, toy_images(scene, toy::Fault::half_step_offset, "end1"), expecting(1));
  EXPECT_TRUE(r.pass) << r.verdict.reason;
  EXPECT_FALSE(has_fault(r, FaultKind::half_step_offset));
  ASSERT_FALSE(r.conventions.empty());
  EXPECT_EQ(r.conventions[0].behaviour, "samples at the end of each step");
}

TEST(Conventions, OnlyAPatternWithAnImpliedOrderAtTheExpectedOneIsAConvention) {
  VerifyOptions o;
  const Fault offset{FaultKind::half_step_offset, "e", "samples at the start of each step", 1};
  const Fault floor{FaultKind::constant_floor, "e"};
  EXPECT_FALSE(consistent_with_expected_order(offset, o));  // no expected order: a fault
  o.expected_order = 1.2;
  EXPECT_TRUE(consistent_with_expected_order(offset, o));   // 1 >= 1.2 - 0.25
  EXPECT_FALSE(consistent_with_expected_order(floor, o));   // no implied order
  o.expected_order = 1.3;
  EXPECT_FALSE(consistent_with_expected_order(offset, o));
  VerifyReport r;
  r.faults = {offset, floor};
  o.expected_order = 1;
  separate_conventions(r, o);
  ASSERT_EQ(r.faults.size(), 1u);
  EXPECT_EQ(r.faults[0].kind, FaultKind::constant_floor);
  ASSERT_EQ(r.conventions.size(), 1u);
  EXPECT_EQ(r.conventions[0].kind, FaultKind::half_step_offset);
}

}  // namespace
}  // namespace vrv::verify_toy

namespace vrv::verify_toy {
namespace {

// A correct renderer of each common placement (tests/lib/toy_raycaster.h, not vrv's raycaster),
// verified at the order it is meant to have: matched by vrv's model of that placement to within
// 1e-6 of its own error, and no fault named.
// The images' own RMS error against the reference, over every image.
double own_rms(const VerifyReport& r) {
  double sum = 0;
  for (const ChannelReport& ch : r.channels) sum += ch.all().rms * ch.all().rms;
  return std::sqrt(sum / static_cast<double>(r.channels.size()));
}

struct PlacementCase {
  toy::Placement placement;
  double expected_order;
  std::string model;  // the nearest model's placement
};

class CorrectPlacements : public VerifyToy, public ::testing::WithParamInterface<PlacementCase> {};

TEST_P(CorrectPlacements, AreMatchedExactlyAndNoFaultIsNamed) {
  const PlacementCase& c = GetParam();
  const auto images = images_in_memory(
      scene, [&](double h) { return toy::render(scene, *scene.camera, h, c.placement); }, c.model);
  const VerifyReport r = verify_images(scene, images, expecting(c.expected_order));
  EXPECT_TRUE(r.pass) << r.verdict.reason;
  for (const Fault& f : r.faults) ADD_FAILURE() << f.name() << ": " << f.evidence;
  ASSERT_FALSE(r.diagnosis.empty());
  const Candidate& best = r.diagnosis.front();
  EXPECT_EQ(best.placement, c.model) << best.name;
  EXPECT_EQ(best.rule, "alpha") << best.name;
  const double own = own_rms(r);
  const double ratio = best.rms / own;
  EXPECT_LE(ratio, 1e-6) << best.name << ": " << best.rms << " against its own error " << own;
  std::cout << c.model << ": nearest model " << best.rms << " RMS, own error " << own << " RMS, ratio " << ratio
            << "\n";
}

INSTANTIATE_TEST_SUITE_P(Toy, CorrectPlacements,
                         ::testing::Values(PlacementCase{toy::Placement::rounded, 2, "inviwo"},
                                           PlacementCase{toy::Placement::partial_at_exit, 2, "partial"},
                                           PlacementCase{toy::Placement::exit_anchored, 2, "exit_anchored"},
                                           PlacementCase{toy::Placement::one_step_in, 1, "vtk"}),
                         [](const auto& info) { return info.param.model; });

// Pre-integration (exact segments between the midpoints, tests/lib/toy_raycaster.h's own
// quadrature): matched by vrv's exact_linear rule at the rounded placement, no fault named.
TEST_F(VerifyToy, PreIntegrationIsMatchedExactlyAndNoFaultIsNamed) {
  const auto images = images_in_memory(
      scene, [&](double h) { return toy::render_preintegrated(scene, *scene.camera, h); }, "preintegrated");
  const VerifyReport r = verify_images(scene, images, expecting(2));
  EXPECT_TRUE(r.pass) << r.verdict.reason;
  for (const Fault& f : r.faults) ADD_FAILURE() << f.name() << ": " << f.evidence;
  ASSERT_FALSE(r.diagnosis.empty());
  const Candidate& best = r.diagnosis.front();
  EXPECT_EQ(best.placement, "inviwo") << best.name;
  EXPECT_EQ(best.rule, "exact_linear") << best.name;
  const double own = own_rms(r);
  EXPECT_LE(best.rms / own, 1e-6) << best.name << ": " << best.rms << " against its own error " << own;
  std::cout << "pre-integration: nearest model " << best.rms << " RMS, own error " << own << " RMS, ratio "
            << best.rms / own << "\n";
}

}  // namespace
}  // namespace vrv::verify_toy
