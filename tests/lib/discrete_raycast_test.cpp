// Discrete raycasts against the reference: convergence orders, exact cases, compositing order,
// classification, termination, float precision.
#include "lib/discrete_raycast.h"
#include "lib/order_estimate.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "lib/reference_integrator.h"

namespace vrv {
namespace {

const Box kBox;

TransferFunction linear_tf() {  // g = f, tau = f / 2: no kink inside (0, 1)
  return TransferFunction::emission_extinction(PiecewiseLinear({{0, 0}, {1, 1}}),
                                               PiecewiseLinear({{0, 0}, {1, 0.5}}));
}

TransferFunction smooth_nonproportional_tf() {  // linear pieces, kinks only outside the ray's values
  return TransferFunction::emission_extinction(PiecewiseLinear({{-1, 1.5}, {2, 0}}),
                                               PiecewiseLinear({{-1, 0.1}, {2, 2.5}}));
}

DiscreteConfig config(SegmentRule rule, Strategy strategy, double step_or_rate) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = strategy;
  if (strategy == Strategy::step || strategy == Strategy::vtk || strategy == Strategy::inviwo)
    c.sampling.step = step_or_rate;
  else
    c.sampling.rate = step_or_rate;
  return c;
}

template <class F>
OrderEstimate order_on(const F& field, const TransferFunction& tf, SegmentRule rule, const Ray& ray) {
  const double reference = integrate_reference(field, kBox, tf, 0.0, ray, {1e-14}).value;
  std::vector<double> steps, errors;
  for (double h : {0.025, 0.0125, 0.00625, 0.003125}) {  // the asymptotic range
    const DiscreteRaycaster raycaster(field, kBox, tf, 0.0, config(rule, Strategy::inviwo, h));
    steps.push_back(h);
    errors.push_back(std::abs(raycaster.cast(ray).value - reference));
  }
  return estimate_order(steps, errors);
}

struct ExpectedOrder {
  SegmentRule rule;
  double order;
};

// Riemann's eq. (5) leaves each sample unattenuated by itself: first order.  The alpha rule
// integrates a piecewise-constant medium exactly, so with midpoint samples it is second order;
// trapezoid, exact_linear and Moreland's average opacity (whose zeta error is O(D^4) per
// segment and whose Psi is exact for constant tau) are second order.
const ExpectedOrder kOrders[] = {
    {SegmentRule::riemann, 1},   {SegmentRule::alpha, 2},    {SegmentRule::trapezoid, 2},
    {SegmentRule::exact_linear, 2}, {SegmentRule::moreland, 2},
};

TEST(DiscreteRaycast, ObservedOrdersOnSmoothRaysMatchTheExpectedOnes) {
  const MarschnerLobb ml{2, 0.25};  // low frequency: the asymptotic range starts early
  const Ray ray = make_ray(Vec3(-3, 0.13, 0.21), Vec3(1, 0.07, -0.05));
  for (const auto& e : kOrders) {
    // The tolerance derived from the fit's own spread (lib/order_estimate.h): max(2 x 4.80 x SE, 0.05)
    // on these four halving steps, as in the studies.
    const OrderEstimate fit = order_on(ml, smooth_nonproportional_tf(), e.rule, ray);
    EXPECT_TRUE(order_matches(fit, e.order, OrderTolerance{2, 0.05}))
        << segment_rule_name(e.rule) << ": " << fit.order << ", SE " << fit.standard_error << ", tolerance "
        << order_tolerance(fit, OrderTolerance{2, 0.05});
  }
}

TEST(DiscreteRaycast, ExactLinearIsExactOnARampWithALinearTransferFunction) {
  const LinearRamp ramp{Vec3(0.3, 0.2, -0.1), 0.5};
  const TransferFunction tf = smooth_nonproportional_tf();
  for (const Ray& ray : {make_ray(Vec3(-3, 0.1, 0.2), Vec3(1, 0.1, 0.05)),
                         make_ray(Vec3(0.2, -3, 0.4), Vec3(-0.2, 1, 0.3))}) {
    const double reference = integrate_reference(ramp, kBox, tf, 0.3, ray).value;
    for (double h : {0.7, 0.13, 0.01}) {
      const DiscreteRaycaster raycaster(ramp, kBox, tf, 0.3, config(SegmentRule::exact_linear, Strategy::step, h));
      EXPECT_NEAR(raycaster.cast(ray).value, reference, 1e-14) << "h = " << h;
    }
  }
}

TEST(DiscreteRaycast, FrontToBackAndBackToFrontAgree) {
  const MarschnerLobb ml;
  const Ray ray = make_ray(Vec3(-3, 0.3, -0.2), Vec3(1, -0.1, 0.08));
  for (const auto& e : kOrders) {
    DiscreteConfig c = config(e.rule, Strategy::entry_exit_corner, 2);
    const double ftb = DiscreteRaycaster(ml, kBox, linear_tf(), 0.4, c).cast(ray).value;
    c.compositing = Compositing::back_to_front;
    const double btf = DiscreteRaycaster(ml, kBox, linear_tf(), 0.4, c).cast(ray).value;
    EXPECT_NEAR(ftb, btf, 1e-14 * std::abs(ftb)) << segment_rule_name(e.rule);
  }
}

// What Lacroute's correction does with the paper's placement (oversamples from the unit sample on,
// every dx / N): it keeps the uncorrected raycast's samples, changes nothing at N = 1, and makes
// each opacity that of a step dx / N, so it composites less than the uncorrected oversampling.
// It does not equal the alpha raycast at dx / N (those samples start at dx / (2N), these at dx / 2):
// that equality holds for centred oversamples, the next test.
TEST(DiscreteRaycast, LacrouteOversamplingKeepsTheSamplesAndCompositesLessThanUncorrected) {
  const MarschnerLobb ml;
  const Ray ray = make_ray(Vec3(-3, 0.3, -0.2), Vec3(1, -0.1, 0.08));
  for (int N : {1, 2, 5, 1024}) {
    DiscreteConfig coarse = config(SegmentRule::alpha, Strategy::step, 0.1);
    coarse.oversample = N;
    coarse.correction = Correction::lacroute;
    const DiscreteResult a = DiscreteRaycaster(ml, kBox, linear_tf(), 0, coarse).cast(ray);
    DiscreteConfig fine = config(SegmentRule::alpha, Strategy::step, 0.1);
    fine.oversample = N;  // same sample positions, no correction: over-composites
    const DiscreteResult b = DiscreteRaycaster(ml, kBox, linear_tf(), 0, fine).cast(ray);
    EXPECT_TRUE(std::isfinite(a.value));
    EXPECT_EQ(a.samples, b.samples);
    if (N == 1)
      EXPECT_EQ(a.value, b.value);  // the correction by 1 is the identity
    else
      EXPECT_GT(b.value, a.value) << N;  // uncorrected oversampling is too opaque/bright here
  }
}

TEST(DiscreteRaycast, CentredLacrouteOversamplingIsTheAlphaRaycastAtTheFineStep) {
  // Centred oversamples of a step-strategy plan sit at entry + (m + 1/2) dx / N: the positions of
  // the step strategy at dx / N; Lacroute makes the opacities those of dx / N too.
  const MarschnerLobb ml;
  const Ray ray = make_ray(Vec3(-3, 0.3, -0.2), Vec3(1, -0.1, 0.08));
  for (int N : {2, 5, 64, 1024}) {
    DiscreteConfig over = config(SegmentRule::alpha, Strategy::step, 0.1);
    over.oversample = N;
    over.centred_oversamples = true;
    over.correction = Correction::lacroute;
    const DiscreteResult a = DiscreteRaycaster(ml, kBox, linear_tf(), 0, over).cast(ray);
    const DiscreteResult b =
        DiscreteRaycaster(ml, kBox, linear_tf(), 0, config(SegmentRule::alpha, Strategy::step, 0.1 / N)).cast(ray);
    EXPECT_NEAR(a.value, b.value, 1e-12) << N;
    EXPECT_LE(std::abs(a.samples - b.samples), 1) << N;
  }
}

TEST(DiscreteRaycast, CentredOversamplesNeedAStrategyThatStartsHalfAStepIn) {
  for (Strategy st : {Strategy::eye, Strategy::entry, Strategy::entry_exit, Strategy::entry_exit_corner}) {
    DiscreteConfig c;
    c.sampling.strategy = st;
    c.oversample = 4;
    c.centred_oversamples = true;
    EXPECT_THROW(validate(c, false), std::invalid_argument) << strategy_name(st);
  }
  DiscreteConfig ok = config(SegmentRule::alpha, Strategy::step, 0.1);
  ok.centred_oversamples = true;
  EXPECT_NO_THROW(validate(ok, false));
}

TEST(DiscreteRaycast, EntryExitDropsACornerRayAndCornerKeepsIt) {
  const MarschnerLobb ml;
  // Chord of length ~0.01 across the edge x = y = 1.
  const Vec3 dir = Vec3(1, -1, 0).normalized();
  const Ray ray = make_ray(Vec3(0.995, 1.0, 0.3) - 3 * dir, dir);
  const auto drop = DiscreteRaycaster(ml, kBox, linear_tf(), 0, config(SegmentRule::riemann, Strategy::entry_exit, 1)).cast(ray);
  const auto keep = DiscreteRaycaster(ml, kBox, linear_tf(), 0, config(SegmentRule::riemann, Strategy::entry_exit_corner, 1)).cast(ray);
  EXPECT_EQ(drop.samples, 0);
  EXPECT_EQ(drop.value, 0);
  EXPECT_GE(keep.samples, 1);
  const double reference = integrate_reference(ml, kBox, linear_tf(), 0, ray).value;
  EXPECT_GT(reference, 0);
  EXPECT_NEAR(keep.value, reference, 0.05 * reference);
}

TEST(DiscreteRaycast, PreAndPostClassificationAgreeForALinearTransferFunction) {
  const GridField grid = make_grid(kBox, MarschnerLobb{}, {9, 9, 9}, GridLayout::node, Interpolation::trilinear);
  const Ray ray = make_ray(Vec3(-3, 0.3, -0.2), Vec3(1, -0.1, 0.08));
  DiscreteConfig c = config(SegmentRule::trapezoid, Strategy::entry_exit_corner, 2);
  const double post = DiscreteRaycaster(grid, kBox, linear_tf(), 0, c).cast(ray).value;
  c.classification = Classification::pre;
  const double pre = DiscreteRaycaster(grid, kBox, linear_tf(), 0, c).cast(ray).value;
  EXPECT_NEAR(pre, post, 1e-14);  // affine classification commutes with interpolation
  const TransferFunction step = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {0.5, 0}, {0.5, 1}, {1, 1}}), PiecewiseLinear({{0, 0.1}, {0.5, 0.1}, {0.5, 2}, {1, 2}}));
  const double pre_step = DiscreteRaycaster(grid, kBox, step, 0, c).cast(ray).value;
  c.classification = Classification::post;
  const double post_step = DiscreteRaycaster(grid, kBox, step, 0, c).cast(ray).value;
  EXPECT_GT(std::abs(pre_step - post_step), 1e-6);  // a step transfer function does not commute
}

// The Riemann loop most configurations take (front to back, no skipping or termination, post-
// classified: detail::plain_riemann) is the general loop without its checks: bit for bit the value
// and samples of the general loop, forced here by a skip threshold of 0 (which skips nothing), on
// a grid of each interpolation, an analytic field, both precisions, with and without tables.
TEST(DiscreteRaycast, PlainRiemannLoopIsBitwiseTheGeneralOne) {
  const MarschnerLobb ml;
  const GridField trilinear = make_grid(kBox, ml, {9, 8, 10}, GridLayout::node, Interpolation::trilinear);
  const GridField nearest = make_grid(kBox, ml, {9, 8, 10}, GridLayout::cell, Interpolation::nearest);
  const TransferFunction kinked = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {0.4, 0.9}, {1, 0.2}}), PiecewiseLinear({{0, 0.1}, {0.6, 3}, {1, 1}}));
  int compared = 0;
  const auto compare = [&](const auto& field, const DiscreteConfig& plain) {
    DiscreteConfig general = plain;
    general.skip_below = 0.0;
    const DiscreteRaycaster a(field, kBox, kinked, 0.25, plain), b(field, kBox, kinked, 0.25, general);
    for (int i = 0; i < 12; ++i) {
      const Vec3 target(0.3 * std::sin(i), 0.4 * std::cos(1.7 * i), 0.2 * i / 12.0 - 0.1);
      const Vec3 origin(-3 + 0.5 * std::cos(i), 2 * std::sin(0.3 * i), -1.5 + 0.2 * i);
      const Ray ray = make_ray(origin, target - origin);
      const DiscreteResult x = a.cast(ray), y = b.cast(ray);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(x.value), std::bit_cast<std::uint64_t>(y.value)) << i;
      EXPECT_EQ(x.samples, y.samples) << i;
      ++compared;
    }
  };
  for (const Precision precision : {Precision::double_precision, Precision::single_precision})
    for (const int table : {0, 64}) {
      DiscreteConfig c = config(SegmentRule::riemann, Strategy::inviwo, 0.013);
      c.precision = precision;
      c.table_size = table;
      compare(trilinear, c);
      compare(nearest, c);
      compare(ml, c);
    }
  EXPECT_EQ(compared, 2 * 2 * 3 * 12);
}

TEST(DiscreteRaycast, EarlyTerminationSavesSamplesAndBoundsTheChange) {
  const MarschnerLobb ml;
  const TransferFunction dense = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {1, 1}}), PiecewiseLinear({{0, 0}, {1, 8}}));
  const Ray ray = make_ray(Vec3(-3, 0.3, -0.2), Vec3(1, -0.1, 0.08));
  DiscreteConfig c = config(SegmentRule::alpha, Strategy::entry_exit_corner, 2);
  const DiscreteResult full = DiscreteRaycaster(ml, kBox, dense, 0, c).cast(ray);
  for (double threshold : {0.95, 0.99}) {
    c.termination = threshold;
    const DiscreteResult cut = DiscreteRaycaster(ml, kBox, dense, 0, c).cast(ray);
    EXPECT_LT(cut.samples, full.samples);
    // What is dropped is attenuated by at most 1 - threshold, times the largest colour (1/8).
    EXPECT_LE(std::abs(cut.value - full.value), (1 - threshold) * 0.125 + 1e-15);
  }
}

TEST(DiscreteRaycast, FloatRoundOffOvertakesTruncationAtTinySteps) {
  const MarschnerLobb ml{2, 0.25};
  const Ray ray = make_ray(Vec3(-3, 0.13, 0.21), Vec3(1, 0.07, -0.05));
  const TransferFunction tf = smooth_nonproportional_tf();
  const double reference = integrate_reference(ml, kBox, tf, 0, ray).value;
  auto error = [&](Precision p, double h) {
    DiscreteConfig c = config(SegmentRule::trapezoid, Strategy::step, h);
    c.precision = p;
    return std::abs(DiscreteRaycaster(ml, kBox, tf, 0, c).cast(ray).value - reference);
  };
  // At a coarse step both are truncation-dominated and agree; at a tiny step double keeps
  // improving while float has hit its rounding floor.
  EXPECT_NEAR(error(Precision::single_precision, 0.1), error(Precision::double_precision, 0.1),
              0.01 * error(Precision::double_precision, 0.1) + 1e-6);
  EXPECT_GT(error(Precision::single_precision, 1e-4), 10 * error(Precision::double_precision, 1e-4));
  EXPECT_TRUE(std::isfinite(error(Precision::single_precision, 1e-5)));
}

TEST(DiscreteRaycast, RejectsMeaninglessCombinations) {
  DiscreteConfig c;
  c.correction = Correction::lacroute;  // with riemann
  EXPECT_THROW(validate(c, false), std::invalid_argument);
  c = DiscreteConfig{};
  c.classification = Classification::pre;
  EXPECT_THROW(validate(c, false), std::invalid_argument);
  EXPECT_NO_THROW(validate(c, true));
  c = DiscreteConfig{};
  c.termination = 0.95;
  c.compositing = Compositing::back_to_front;
  EXPECT_THROW(validate(c, false), std::invalid_argument);
  c = DiscreteConfig{};
  c.oversample = 0;
  EXPECT_THROW(validate(c, false), std::invalid_argument);
}

}  // namespace
}  // namespace vrv
