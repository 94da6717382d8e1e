// The reference integrator against an independent long-double reference (independent_reference.h,
// through reference_check.h: every vrv integration in a guarded child, honest and within its
// tolerance): high frequency, background, cost, looser tolerances, ramps, hard rays, far origins
// and tight estimates.  The transfer-function classes are in transfer_function_test.cpp, the grid
// layouts in grid_field_test.cpp, the oracle's own tests in independent_reference_test.cpp.
// Every case prints its mean evaluations.
#include "lib/reference_integrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "analytic/linear_ramp.h"
#include "analytic/marschner_lobb.h"
#include "lib/grid_field.h"
#include "lib/scene.h"
#include "tests/lib/reference_check.h"

namespace vrv {
namespace {

using namespace reference_check;

// ------------------------------------------------------------------------------------------
// Marschner-Lobb, random rays.

TEST(ReferenceIntegratorMarschnerLobb, HighFrequency) {
  check_rays("ML fM=12 (b)", MarschnerLobb{12, 0.25}, ind::MarschnerLobbLD{12, 0.25L}, tf_general(),
             0, random_rays(5, 6));
}

TEST(ReferenceIntegratorMarschnerLobb, Background) {
  // Background 0.7, through the Scene overload.
  Scene scene;
  scene.box = kBox;
  scene.field = kML;
  scene.transfer = tf_general();
  scene.background = 0.7;
  const auto rays = random_rays(10, 8);
  const std::vector<ind::Result> refs = references(kMLRef, scene.transfer, 0.7L, rays);
  Stats stats;
  for (std::size_t i = 0; i < rays.size(); ++i)
    compare([&] { return integrate_reference(scene, make_ray(rays[i].origin, rays[i].direction), {kTol}); },
            refs[i], rays[i], &stats);
  report("ML (b) background 0.7", stats);
}

TEST(ReferenceIntegratorMarschnerLobb, MeanEvaluations) {
  // Cost at tol 1e-12 for the non-proportional transfer function (b).
  const TransferFunction tf = tf_general();
  const auto rays = random_rays(30, 2);
  long total = 0;
  double seconds = 0;
  for (const auto& spec : rays) {
    const auto start = std::chrono::steady_clock::now();
    const auto r = guarded([&] {
      return integrate_reference(kML, kBox, tf, 0, make_ray(spec.origin, spec.direction), {kTol});
    });
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(r) << "vrv did not finish: " << describe(spec);
    total += r->evaluations;
  }
  const double mean = static_cast<double>(total) / static_cast<double>(rays.size());
  std::cout << "[ ML (b) tol 1e-12 ] mean evaluations per ray " << mean << " ("
            << 1e3 * seconds / static_cast<double>(rays.size())
            << " ms per ray, including a fork)\n";
  RecordProperty("mean_evaluations", std::to_string(mean));
  // Regression bound, not derived: measured 257.4 evaluations per ray (this test's output; at tol
  // 1e-12 these short rays keep the global sizing, lib/reference_integrator.h kMergeTolerance), the
  // bound leaves room for the (machine-independent) work to grow 2x before it trips.
  EXPECT_LE(mean, 600);
}

// ------------------------------------------------------------------------------------------
// Linear ramp.

TEST(ReferenceIntegratorLinearRamp, GeneralAndStepTransfer) {
  const LinearRamp ramp{{0.3, 0.2, -0.1}, 0.5};
  const ind::LinearRampLD ref(ramp.gradient, 0.5L);
  check_rays("ramp (b)", ramp, ref, tf_general(), 0, random_rays(15, 11));
  check_rays("ramp (c)", ramp, ref, tf_step(), 0, random_rays(15, 12));
}

// ------------------------------------------------------------------------------------------
// Hard cases.

TEST(ReferenceIntegratorHard, OpticalDepthInThousands) {
  // Extinction of (b) times 2000: the transmittance underflows early; nothing may become NaN
  // and the integrator must stop spending evaluations once the rest cannot matter.
  const TransferFunction tf = scaled_extinction(kEmissionB, kExtinctionB, 2000);
  std::vector<RaySpec> rays{{{-3, 0.1, 0.2}, {1, 0, 0}}, {{-2.5, -2.6, 2.4}, {1, 1, -1}}};
  for (const auto& r : random_rays(4, 31)) rays.push_back({r.origin, -r.origin});  // via the centre
  for (const auto& spec : rays) {
    ind::Result ref;
    const auto r = check_ray(kML, kMLRef, tf, 0, spec, &ref);
    if (!r) continue;
    // The ray stops once opaque (stop_when_opaque): its depth is the depth up to there.
    EXPECT_TRUE(r->stopped_early) << describe(spec);
    EXPECT_LE(r->optical_depth, static_cast<double>(ref.optical_depth)) << describe(spec);
    EXPECT_GT(static_cast<double>(ref.optical_depth), 1000) << describe(spec);
    // Regression bound on the work, not derived: measured at most 396 evaluations on these rays
    // (this test's output, "[ depth x2000 ]"); a ray that stops paying once the rest cannot
    // matter stays far below it, one that integrates the opaque remainder does not.
    EXPECT_LT(r->evaluations, 5000) << describe(spec);
    // Carried to the exit, the depth is the whole depth and the value the same.
    ReferenceOptions whole{kTol};
    whole.stop_when_opaque = false;
    const ReferenceResult w =
        integrate_reference(kML, kBox, tf, 0, make_ray(spec.origin, spec.direction), whole);
    EXPECT_FALSE(w.stopped_early);
    EXPECT_NEAR(w.optical_depth, static_cast<double>(ref.optical_depth), 1e-9 * w.optical_depth)
        << describe(spec);
    EXPECT_EQ(w.value, r->value) << describe(spec);
    EXPECT_LT(w.evaluations, 5000) << describe(spec);
    std::cout << std::setprecision(6) << "[ depth x2000 ] value " << r->value << ", estimate "
              << r->error_estimate << ", depth " << r->optical_depth << " (independent "
              << static_cast<double>(ref.optical_depth) << "), evaluations " << r->evaluations
              << "\n";
  }
}

TEST(ReferenceIntegratorHard, TinyExtinction) {
  const TransferFunction tf = scaled_extinction(kEmissionB, kExtinctionB, 1e-12);
  const TransferFunction none = scaled_extinction(kEmissionB, kExtinctionB, 0);
  for (const auto& spec : random_rays(3, 41)) {
    const auto r = check_ray(kML, kMLRef, tf, 0, spec);
    // With no extinction at all the value is int g.
    const ind::Result plain =
        ind::independent_integral(kMLRef, kBox, none, 0, spec.origin, spec.direction);
    if (r) {
      EXPECT_NEAR(r->value, static_cast<double>(plain.value), 1e-11) << describe(spec);
    }
    check_ray(kML, kMLRef, none, 0, spec);
  }
}

// Looser tolerances start from longer panels (first_panel_phase): every ray stays honest against
// the independent integral and within its tolerance, and the work falls with the tolerance.
TEST(ReferenceIntegratorMarschnerLobb, LooseTolerancesAreHonestAndCheaper) {
  const TransferFunction tf = tf_general();
  const std::vector<RaySpec> rays = random_rays(12, 2026);
  const std::vector<ind::Result> refs = references(kMLRef, tf, 0, rays);
  std::vector<double> mean_evaluations;
  for (double tol : {1e-2, 1e-4, 1e-6, 1e-8, 1e-12}) {
    Stats stats;
    for (std::size_t i = 0; i < rays.size(); ++i)
      compare([&] {
        return integrate_reference(kML, kBox, tf, 0, make_ray(rays[i].origin, rays[i].direction), {tol});
      }, refs[i], rays[i], &stats, tol);
    EXPECT_EQ(stats.dishonest, 0) << tol;
    mean_evaluations.push_back(stats.mean_evaluations());
  }
  for (std::size_t k = 1; k < mean_evaluations.size(); ++k)
    EXPECT_LE(mean_evaluations[k - 1], mean_evaluations[k]) << k;
  EXPECT_LT(mean_evaluations.front(), 0.75 * mean_evaluations.back());
}

TEST(ReferenceIntegratorHard, RayWhereTheFieldIsNearZero) {
  // Marschner-Lobb stays near 4e-4 over the first third of this chord (the speed-vs-error study's
  // ray 217): its values there are O(1) terms cancelling, noisy at ~1e-15 absolute.  Judged
  // relative to f the panels never resolved and the ray took the 1e6-evaluation work cap.
  const RaySpec spec{{3.6837434472506665, 2.5433031067114187, 2.6384926610149635},
                     {-0.62336032826786514, -0.69731403074862053, -0.35380085311215842}};
  const auto r = check_ray(kML, kMLRef, tf_general(), 0, spec);
  ASSERT_TRUE(r);
  std::cout << "[ near-zero field ] evaluations " << r->evaluations << "\n";
  // Regression bound on the work, not derived: measured 66 evaluations; the failure it guards
  // against took the 1e6-evaluation work cap.
  EXPECT_LT(r->evaluations, 2000);
}

TEST(ReferenceIntegratorHard, RayAlongBoxEdge) {
  const RaySpec spec{{-2, 1, 1}, {1, 0, 0}};
  const auto r = check_ray(kML, kMLRef, tf_general(), 0, spec);
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->hit);
  EXPECT_EQ(r->t_entry, 1);
  EXPECT_EQ(r->t_exit, 3);
  check_ray(kML, kMLRef, tf_step(), 0, spec);
  const GridField grid = make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::trilinear);
  check_ray(grid, ind::GridLD(grid), tf_general(), 0, spec);
}

TEST(ReferenceIntegratorHard, RayAlongBoxFace) {
  const RaySpec spec{{-2, 0.3, 1}, {1, 0, 0}};
  const auto r = check_ray(kML, kMLRef, tf_general(), 0, spec);
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->hit);
  check_ray(kML, kMLRef, tf_step(), 0, spec);
  const GridField grid = make_grid(kBox, kML, {8, 8, 8}, GridLayout::cell, Interpolation::trilinear);
  check_ray(grid, ind::GridLD(grid), tf_general(), 0, spec);
}

TEST(ReferenceIntegratorHard, CornerClip) {
  // The segment x + y = 2 - delta, z = 0.5 inside the box: length delta sqrt(2) = 1e-9.
  const double delta = 1e-9 / std::numbers::sqrt2;
  const RaySpec spec{{1 - delta / 2 - 3, 1 - delta / 2 + 3, 0.5}, {1, -1, 0}};
  for (const auto& tf : {tf_general(), tf_proportional(), tf_step()}) {
    ind::Result ref;
    const auto r = check_ray(kML, kMLRef, tf, 0.25, spec, &ref);
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->hit);
    const double length = r->t_exit - r->t_entry;
    EXPECT_GT(length, 0.5e-9);
    EXPECT_LT(length, 2e-9);
    EXPECT_LT(std::abs(r->value - 0.25), 1e-8);
    std::cout << std::setprecision(17) << "[ corner ] length " << length << " (independent "
              << static_cast<double>(ref.t_exit - ref.t_entry) << "), value - background "
              << r->value - 0.25 << " (independent " << static_cast<double>(ref.value - 0.25L)
              << ")\n";
  }
}

TEST(ReferenceIntegratorHard, RayStartingInside) {
  const RaySpec spec{{0.1, -0.2, 0.3}, {0.3, 0.5, -0.7}};
  const auto r = check_ray(kML, kMLRef, tf_general(), 0, spec);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->t_entry, 0);
  const GridField grid = make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::nearest);
  check_ray(grid, ind::GridLD(grid), tf_step(), 0, spec);
}

TEST(ReferenceIntegratorHard, AxisParallelRays) {
  const std::vector<RaySpec> rays{{{-3, 0.2, -0.4}, {1, 0, 0}},
                                  {{0.3, -3, 0.1}, {0, 1, 0}},
                                  {{-0.25, 0.6, 3}, {0, 0, -1}}};
  const GridField node = make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::trilinear);
  const GridField cell = make_grid(kBox, kML, {8, 8, 8}, GridLayout::cell, Interpolation::trilinear);
  const GridField near = make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::nearest);
  for (const auto& spec : rays) {
    check_ray(kML, kMLRef, tf_general(), 0, spec);
    check_ray(kML, kMLRef, tf_step(), 0, spec);
    check_ray(node, ind::GridLD(node), tf_general(), 0, spec);
    check_ray(cell, ind::GridLD(cell), tf_general(), 0, spec);
    check_ray(near, ind::GridLD(near), tf_general(), 0, spec);
  }
}

// Issue 10: a 60-unit ray along the axis of Marschner-Lobb at fM = 24 had its panels sized for the
// global bandwidth (pi^2 fM + pi/2 = 238 rad per unit: 895 panels, 29,535 evaluations) where only
// sin(pi z / 2) varies.  Panels are now sized from the field's local bound (bandwidth_between).
// Near-axis and tilted rays, where the radial term is slow but not constant, and one that reaches
// r ~ 1 (the fastest part) check that the longer panels stay honest.
TEST(ReferenceIntegratorHard, LongRayAlongTheAxisIsSizedLocally) {
  const Box box{Vec3(-2, -2, -30), Vec3(2, 2, 30)};
  const MarschnerLobb ml{24, 0.25};
  const ind::MarschnerLobbLD ml_ref{24, 0.25L};
  const std::vector<RaySpec> rays{{{0, 0, -31}, {0, 0, 1}},
                                  {{0.01, 0.02, -31}, {0, 0, 1}},
                                  {{0, 0, -31}, {1e-3, 0, 1}},
                                  {{-0.2, 0.1, -31}, {0.01, -0.005, 1}},
                                  {{-1.05, -0.7, -31}, {0.035, 0.0233, 1}}};
  // Every ray with the general transfer function, the axis ray also with the proportional one.
  for (const auto& tf_count : {std::pair{tf_general(), rays.size()}, std::pair{tf_proportional(), std::size_t{1}}}) {
    const auto& tf = tf_count.first;  // not bindings: clang 14 cannot capture them
    const std::size_t count = tf_count.second;
    const std::vector<RaySpec> some(rays.begin(), rays.begin() + static_cast<std::ptrdiff_t>(count));
    const std::vector<ind::Result> refs = references(ml_ref, tf, 0, some, box);
    for (std::size_t i = 0; i < some.size(); ++i) {
      const RaySpec& spec = some[i];
      const auto r = compare(
          [&] { return integrate_reference(ml, box, tf, 0, make_ray(spec.origin, spec.direction), {kTol}); },
          refs[i], spec);
      ASSERT_TRUE(r);
      std::cout << std::setprecision(4) << "[ fM 24, 60-unit ray " << i << " ] evaluations " << r->evaluations
                << ", estimate " << r->error_estimate << ", |diff| "
                << static_cast<double>(std::abs(static_cast<LD>(r->value) - refs[i].value)) << "\n";
      // The axis ray: 29,535 evaluations with global panels, 198 measured with local ones;
      // the bound is 30x below the former, with room for the splitting to change.
      if (i == 0) {
        EXPECT_LE(r->evaluations, 1000);
      }
    }
  }
}

TEST(ReferenceIntegratorHard, Miss) {
  const ReferenceResult r =
      integrate_reference(kML, kBox, tf_general(), 0.7, make_ray({3, 3, 3}, {1, 0, 0}), {kTol});
  EXPECT_FALSE(r.hit);
  EXPECT_EQ(r.value, 0.7);
  EXPECT_EQ(r.evaluations, 0);
  // Parallel to a face, just outside it.
  const ReferenceResult s = integrate_reference(kML, kBox, tf_general(), 0.7,
                                                make_ray({-2, 1 + 1e-15, 0}, {1, 0, 0}), {kTol});
  EXPECT_FALSE(s.hit);
  EXPECT_EQ(s.value, 0.7);
  // Pointing away from the box.
  const ReferenceResult t =
      integrate_reference(kML, kBox, tf_general(), 0.7, make_ray({-2, 0, 0}, {-1, 0, 0}), {kTol});
  EXPECT_FALSE(t.hit);
  EXPECT_EQ(t.value, 0.7);
}

TEST(ReferenceIntegratorHard, TinyAndHugeDirections) {
  // make_ray must normalise 1e-300- and 1e300-scaled directions without under- or overflow.
  const Vec3 origin(-3, -2.5, 1.5);
  const Vec3 unit_dir(1, 0.75, -0.25);
  const auto base = check_ray(kML, kMLRef, tf_general(), 0, RaySpec{origin, unit_dir});
  ASSERT_TRUE(base);
  // Each scaled direction against the reference for exactly that input (1e-310 makes the
  // components subnormal, which rounds them: a slightly different ray).
  for (double scale : {1e-300, 1e300, 1e-310}) {
    const auto r = check_ray(kML, kMLRef, tf_general(), 0, RaySpec{origin, scale * unit_dir});
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->hit);
  }
  // Power-of-two scales keep the direction exact: the very same ray, the very same result.
  for (double scale : {0x1p-1000, 0x1p+1000}) {
    const ReferenceResult r =
        integrate_reference(kML, kBox, tf_general(), 0, make_ray(origin, scale * unit_dir), {kTol});
    EXPECT_EQ(r.value, base->value) << scale;
    EXPECT_EQ(r.t_entry, base->t_entry) << scale;
    EXPECT_EQ(r.t_exit, base->t_exit) << scale;
  }
}


// ------------------------------------------------------------------------------------------
// Far origins (issue 10): positions origin + t d at t ~ 1e14 lose the digits of t.  The far ray
// starts D = 2^k before a point q near the box on the same line; o + D d is then exact (the
// product by a power of two is exact and the sum cancels, Sterbenz), so the independent
// integral from q is the exact value of the far ray.

namespace far {

struct Case {
  Ray far_ray;
  RaySpec near;  // the same line, from near the box
};

std::vector<Case> cases(const std::vector<RaySpec>& near_rays, int exponent) {
  std::vector<Case> out;
  const double D = std::ldexp(1.0, exponent);
  for (const RaySpec& r : near_rays) {
    const Vec3 d0 = make_ray(r.origin, r.direction).direction;
    const Ray far_ray = make_ray(r.origin - D * d0, d0);
    // The line as given (d0), which normalising again may round by an ulp.
    const Vec3& d = d0;
    const Vec3 q = far_ray.origin + D * d;
    for (int a = 0; a < 3; ++a) {  // q is exact: the same line
      const LD exact = static_cast<LD>(far_ray.origin[a]) + static_cast<LD>(D) * static_cast<LD>(d[a]);
      EXPECT_EQ(static_cast<LD>(q[a]), exact) << exponent;
    }
    out.push_back({far_ray, {q, d}});
  }
  return out;
}

}  // namespace far

TEST(ReferenceIntegratorFarOrigin, HonestTightAndAsCheapAsNear) {
  // Ordinary rays and rays through the centre, in many directions; exponents 7 ... 50 put the
  // origin 1.3e2 ... 1.1e15 away.
  std::vector<RaySpec> near_rays = random_rays(6, 77);
  for (const auto& r : random_rays(2, 78)) near_rays.push_back({r.origin, -r.origin});
  near_rays.push_back({{-3, 0.1, 0.2}, {1, 0, 0}});
  struct Setup {
    const char* name;
    TransferFunction tf;
  };
  for (const Setup& setup : {Setup{"proportional", tf_proportional()}, Setup{"general", tf_general()},
                             Setup{"step", tf_step()}}) {
    const std::vector<ind::Result> refs = references(kMLRef, setup.tf, 0, near_rays);
    std::vector<ReferenceResult> near_results;
    for (const RaySpec& r : near_rays)
      near_results.push_back(integrate_reference(kML, kBox, setup.tf, 0, make_ray(r.origin, r.direction), {kTol}));
    for (int exponent : {7, 17, 27, 37, 47, 50}) {
      Stats stats;
      double worst_cost_ratio = 0, worst_estimate_ratio = 0;
      const std::vector<far::Case> cs = far::cases(near_rays, exponent);
      for (std::size_t i = 0; i < cs.size(); ++i) {
        // The reference of the near ray, for exactly the far ray's line.
        const ind::Result ref = ind::independent_integral(kMLRef, kBox, setup.tf, 0, cs[i].near.origin,
                                                          cs[i].near.direction);
        const auto r = compare([&] { return integrate_reference(kML, kBox, setup.tf, 0, cs[i].far_ray, {kTol}); },
                               ref, cs[i].near, &stats);
        if (!r) continue;
        EXPECT_TRUE(r->tolerance_met) << describe(cs[i].near);
        const ReferenceResult& n = near_results[i];
        worst_cost_ratio = std::max(worst_cost_ratio, static_cast<double>(r->evaluations) / n.evaluations);
        worst_estimate_ratio = std::max(worst_estimate_ratio, r->error_estimate / (n.error_estimate + 1e-16));
        // The cost does not depend on where the origin is; the estimate stays that of a near ray.
        EXPECT_LE(r->evaluations, 1.25 * n.evaluations + 66) << exponent << " " << describe(cs[i].near);
        EXPECT_LE(r->error_estimate, 4 * n.error_estimate + 1e-15) << exponent << " " << describe(cs[i].near);
        EXPECT_NEAR(r->t_exit - r->t_entry, static_cast<double>(ref.t_exit - ref.t_entry),
                    1e-15 * std::ldexp(1.0, exponent) + 1e-14);
      }
      (void)refs;
      std::cout << "[ far " << setup.name << " 2^" << exponent << " ] max |diff| " << stats.max_difference
                << ", max estimate " << stats.max_error_estimate << ", max diff/estimate " << stats.max_ratio
                << ", max evaluations far/near " << worst_cost_ratio << ", max estimate far/near "
                << worst_estimate_ratio << "\n";
    }
  }
}

TEST(ReferenceIntegratorFarOrigin, DefaultSceneAlongX) {
  // vrv ray --origin -1e14,0.1,0.2 --direction 1,0,0 returned 0.6333834 (estimate 1.3e-14)
  // for 0.6335859; at -1e16 a hit with t_entry = t_exit = 1e16 and value 0.
  const TransferFunction tf = tf_proportional();
  const RaySpec near_spec{{-3, 0.1, 0.2}, {1, 0, 0}};
  ind::Result ref;
  const auto near = check_ray(kML, kMLRef, tf, 0, near_spec, &ref);
  ASSERT_TRUE(near);
  for (double x : {-1e2, -1e6, -1e10, -1e14, -1e15, -1e16, -1e17, -1e20}) {
    const RaySpec spec{{x, 0.1, 0.2}, {1, 0, 0}};
    const auto r = compare([&] { return integrate_reference(kML, kBox, tf, 0, make_ray(spec.origin, spec.direction), {kTol}); },
                           ref, spec);
    ASSERT_TRUE(r) << x;
    EXPECT_TRUE(r->hit) << x;
    EXPECT_TRUE(r->tolerance_met) << x;
    EXPECT_GT(r->value, 0.6) << x;
    EXPECT_LE(r->evaluations, near->evaluations + 66) << x;
  }
}

TEST(ReferenceIntegratorFarOrigin, MissesStayMisses) {
  // Far rays beside the box, and a far ray pointing away from it.
  for (double x : {1e3, 1e10, 1e16}) {
    EXPECT_FALSE(integrate_reference(kML, kBox, tf_general(), 0.7, make_ray({-x, 1.5, 0}, {1, 0, 0})).hit);
    EXPECT_FALSE(integrate_reference(kML, kBox, tf_general(), 0.7, make_ray({-x, 0, 0}, {-1, 0, 0})).hit);
    const ReferenceResult r = integrate_reference(kML, kBox, tf_general(), 0.7, make_ray({-x, x, 0}, {1, -1, 0.3}));
    EXPECT_FALSE(r.hit) << x;
    EXPECT_EQ(r.value, 0.7);
  }
}

// ------------------------------------------------------------------------------------------
// Silent failures (issue 12): a NaN with exit 0, and an int overflow that made the answer wrong.

TEST(ReferenceIntegratorHard, HugeExtinctionGivesNoNaN) {
  // The optical depth at a node came out at -17954 (rounding at tau ~ 1e21), e^-Phi overflowed
  // and the Clenshaw integral returned NaN.  The discrete methods give 8.33e-21.
  Box box{Vec3(-1, -1, -1), Vec3(1, 1, 64)};
  const MarschnerLobb ml{2, 0.25};
  const TransferFunction tf = TransferFunction::emission_extinction(curve({{0, 5}}), curve({{0, 0}, {0.4, 6e20}}));
  const Ray ray = make_ray({-3, 0.2, 28.25}, {1, 0.01, -0.02});
  const ReferenceResult r = integrate_reference(ml, box, tf, 0, ray, {kTol});
  std::cout << std::setprecision(6) << "[ tau 6e20 ] value " << r.value << ", estimate " << r.error_estimate
            << ", evaluations " << r.evaluations << "\n";
  ASSERT_TRUE(r.hit);
  EXPECT_TRUE(std::isfinite(r.value));
  EXPECT_TRUE(std::isfinite(r.error_estimate));
  EXPECT_TRUE(r.tolerance_met);
  EXPECT_GE(r.value, 0);
  // f > 0.4 at the entry, where tau = 6e20 is constant: all the light comes from the first
  // ~1e-20 units, I = g / tau (1 - e^-huge) = 5 / 6e20.  (The long-double oracle underflows here.)
  EXPECT_GT(ml.value(ray.at(r.t_entry)), 0.41);
  EXPECT_LE(std::abs(r.value - 5 / 6e20), r.error_estimate + 1e-35);
  EXPECT_LE(r.error_estimate, 1e-3 * r.value);
  // Entering where f < 0.4 (tau rising 0 -> 6e20 with f): the bracket of g / tau.
  const Ray low = make_ray({-3, 0.2, 29.5}, {1, 0.01, -0.02});
  const double f_entry = ml.value(low.at(clip(low, box)->t0));
  const ReferenceResult s = integrate_reference(ml, box, tf, 0, low, {kTol});
  std::cout << std::setprecision(6) << "[ tau 6e20, f at entry " << f_entry << " ] value " << s.value
            << ", estimate " << s.error_estimate << ", evaluations " << s.evaluations << "\n";
  EXPECT_TRUE(std::isfinite(s.value));
  EXPECT_TRUE(s.tolerance_met);
  EXPECT_GE(s.value, 0);
  EXPECT_LE(s.value, 5 / (6e20 * f_entry / 0.4) * 1.5 + s.error_estimate);
}

TEST(ReferenceIntegratorHard, MorePanelsThanAnIntIsRefusedNotWrong) {
  // (b - a) / h0 above INT_MAX became count 1 (undefined behaviour) and a wrong answer with
  // success.  Now the work cap ends the ray, the rest is bounded, and tolerance_met says so.
  const TransferFunction emit_only =
      TransferFunction::emission_extinction(curve({{0, 0}, {1, 1}}), curve({{0, 0}}));
  const MarschnerLobb fast{1e9, 0.25};  // ~1e10 rad per unit: 3e10 / 16 first panels
  const ReferenceResult r = integrate_reference(fast, kBox, emit_only, 0, make_ray({-3, 0.1, 0.2}, {1, 0.2, 0.1}));
  EXPECT_TRUE(r.hit);
  EXPECT_FALSE(r.tolerance_met);
  EXPECT_LE(r.evaluations, detail::kMaxEvaluations + 33);
  EXPECT_TRUE(std::isfinite(r.value));
  EXPECT_GT(r.error_estimate, 0.5);  // most of the ray (length ~2, emission up to 1) is bounded, not known
  // A 1e10-long box: the same with an ordinary field.
  const Box long_box{Vec3(-5e9, -1, -1), Vec3(5e9, 1, 1)};
  const ReferenceResult s = integrate_reference(kML, long_box, emit_only, 0, make_ray({-6e9, 0.1, 0.2}, {1, 0, 0}));
  EXPECT_FALSE(s.tolerance_met);
  EXPECT_LE(s.evaluations, detail::kMaxEvaluations + 33);
  EXPECT_GT(s.error_estimate, 1e9);
  // fM = 1e300 gave an estimate of 1.1 on a value of 0.8 and said nothing.
  const ReferenceResult t = integrate_reference(MarschnerLobb{1e300, 0.25}, kBox, tf_proportional(), 0,
                                                make_ray({-3, 0.1, 0.2}, {1, 0, 0}));
  EXPECT_FALSE(t.tolerance_met);
  EXPECT_TRUE(std::isfinite(t.error_estimate));
}

TEST(ReferenceIntegratorHard, OpaqueRaysStop) {
  // A box of +-1e5 (optical depth ~5e4) cost 26 million evaluations: once e^-Phi (max g times
  // the rest + background) is below the termination share, nothing after matters.
  const Box huge{Vec3(-1e5, -1e5, -1e5), Vec3(1e5, 1e5, 1e5)};
  const Ray ray = make_ray({-2e5, 0.1, 0.2}, {1, 0, 0});
  {
    // Opaque within the first unit: against the independent integral over the first 2 units
    // (the rest is below e^-100).  Marschner-Lobb at |x| ~ 1e5 is itself noisy at ~1e-10 (the
    // coordinates' rounding), which the estimate must cover.
    const TransferFunction tf = scaled_extinction(kEmissionB, kExtinctionB, 100);
    const ReferenceResult r = integrate_reference(kML, huge, tf, 0, ray, {kTol});
    const Box first{Vec3(-1e5, -1e5, -1e5), Vec3(-1e5 + 2, 1e5, 1e5)};
    const ind::Result ref = ind::independent_integral(kMLRef, first, tf, 0, ray);
    std::cout << std::setprecision(17) << "[ box 1e5, tau x100 ] value " << r.value << ", estimate "
              << r.error_estimate << ", evaluations " << r.evaluations << ", depth " << r.optical_depth
              << "; independent (first 2 units) " << static_cast<double>(ref.value) << ", depth "
              << static_cast<double>(ref.optical_depth) << "\n";
    EXPECT_TRUE(r.stopped_early);
    EXPECT_LT(r.evaluations, 5000);
    EXPECT_GT(static_cast<double>(ref.optical_depth), 100);
    EXPECT_LE(r.optical_depth, static_cast<double>(ref.optical_depth));
    EXPECT_LE(std::abs(r.value - static_cast<double>(ref.value)), r.error_estimate + kSlack);
    EXPECT_LE(r.error_estimate, 1e-6);
  }
  {
    const ReferenceResult r = integrate_reference(kML, huge, tf_general(), 0, ray, {kTol});
    std::cout << "[ box 1e5 ] value " << r.value << ", estimate " << r.error_estimate << ", evaluations "
              << r.evaluations << ", depth " << r.optical_depth << "\n";
    EXPECT_TRUE(r.stopped_early);
    EXPECT_LT(r.evaluations, 50000);
    EXPECT_TRUE(std::isfinite(r.value));
  }
}

// ------------------------------------------------------------------------------------------
// Tight, not only honest (issue 10): rays whose estimate was absurdly loose.  Each must be honest,
// `looseness` bounds estimate / max(actual error, the error a double-precision value or field can
// resolve there), and `evaluations` bounds the work.  Exact values from closed forms (ramps) or
// the independent long-double integral (Marschner-Lobb).

struct TightRow {
  const char* name;
  double value, exact, estimate, resolvable, looseness;
  long evaluations, max_evaluations;
};

void check_tight(const TightRow& row) {
  const double actual = std::abs(row.value - row.exact);
  const double ratio = row.estimate / std::max({actual, row.resolvable, std::numeric_limits<double>::denorm_min()});
  std::cout << std::setprecision(3) << "[ tight ] " << row.name << ": value " << row.value << ", exact " << row.exact
            << ", actual error " << actual << ", estimate " << row.estimate << ", estimate / max(actual, resolvable) "
            << ratio << ", evaluations " << row.evaluations << "\n";
  EXPECT_TRUE(std::isfinite(row.value)) << row.name;
  EXPECT_LE(actual, row.estimate + std::numeric_limits<double>::denorm_min()) << row.name;
  EXPECT_LE(ratio, row.looseness) << row.name;
  EXPECT_LE(row.evaluations, row.max_evaluations) << row.name;
}

TEST(ReferenceIntegratorTight, LooseEstimateTable) {
  const LinearRamp ramp{{0.5, 0, 0}, 0.5};  // v = 0.5 + x / 2 along x
  const Ray along_x = make_ray({-3, 0.1, 0.2}, {1, 0, 0});
  struct Row {
    const char* name;
    LinearRamp field;
    TransferFunction tf;
    double exact;
    double resolvable;  // what the value's or the field's rounding allows
  };
  const double eps = std::numeric_limits<double>::epsilon();
  // Emission E for v > 0.9 (x > 0.8) behind optical depth D = 1.8 tau.
  const auto behind = [](double emission, double tau) {
    return TransferFunction::emission_extinction(curve({{0, 0}, {0.9, 0}, {0.9, emission}, {1, emission}}),
                                                 curve({{0, tau}}));
  };
  const auto behind_exact = [](double emission, double tau) {
    return emission * (std::exp(-tau * 1.8) - std::exp(-tau * 2.0)) / tau;
  };
  const std::vector<Row> rows{
      // Estimate 6.1e285 for an error of 1e-19 before (the bound lacked the e^-Phi).
      {"emission 1e300 behind depth 700", ramp, behind(1e300, 389), behind_exact(1e300, 389), 0},
      // The same at an ordinary emission and depth, I ~ 0.06.
      {"emission 1e12 behind depth 27.6", ramp, behind(1e12, 27.6 / 1.8), behind_exact(1e12, 27.6 / 1.8), 0},
      // A step crossed by a ramp of gradient 1e-13 at x = 0: the rounding of v (~ulp(0.5)) moves
      // the crossing by ulp(0.5) / 1e-13, times the jumps (2.2e-2 before).
      {"gradient 1e-13 crossing a step", LinearRamp{{1e-13, 0, 0}, 0.5}, tf_step(),
       std::exp(-0.1) * (1 - std::exp(-2.0)) / 2, 0.5 * eps / 1e-13 * (1 + 1.9)},
      // Constant emission behind extinction 1e300: I = 1 / 1e300 (1.8e284, then 1.95e-15 before:
      // the rounding of the piece's own depth 2e300 was charged to its own emission).
      {"constant emission behind extinction 1e300", ramp,
       TransferFunction::emission_extinction(curve({{0, 1}}), curve({{0, 1e300}})), 1e-300, eps * 1e-300},
  };
  for (const Row& row : rows) {
    const ReferenceResult r = integrate_reference(row.field, kBox, row.tf, 0, along_x, {kTol});
    check_tight({row.name, r.value, row.exact, r.error_estimate, row.resolvable, 1000, r.evaluations, 2});
  }
}

TEST(ReferenceIntegratorTight, SteepTransferFunctions) {
  // A transfer function rising by 1 over 1e-10 of value (slope 1e10) on the default scene's field:
  // estimate 5.6e-5 for an actual error of 1.4e-15 before (the pieces next to the steep branch
  // took its slope for their own rounding floor).
  const std::vector<std::pair<const char*, TransferFunction>> tfs{
      {"emission slope 1e10", TransferFunction::emission_extinction(
                                  curve({{0, 0}, {0.5, 0}, {0.5 + 1e-10, 1}, {1, 1}}), curve({{0, 0}, {1, 0.5}}))},
      {"extinction slope 1e10", TransferFunction::emission_extinction(
                                    curve({{0, 0}, {1, 1}}), curve({{0, 0}, {0.5, 0}, {0.5 + 1e-10, 1}, {1, 1}}))},
      {"emission and extinction slope 1e10",
       TransferFunction::emission_extinction(curve({{0, 0}, {0.5, 0}, {0.5 + 1e-10, 1}, {1, 1}}),
                                             curve({{0, 0}, {0.5, 0}, {0.5 + 1e-10, 0.5}, {1, 0.5}}))},
      {"emission slope 1e10 at v = 0", TransferFunction::emission_extinction(curve({{0, 0}, {1e-10, 1}}),
                                                                             curve({{0, 0}, {1, 0.5}}))}};
  const std::vector<RaySpec> rays{{{-3, 0.5, 0}, {1, 0, 0}}, {{-3, -2.5, 1.5}, {1, 0.75, -0.25}}};
  for (const auto& [name, tf] : tfs) {
    for (const RaySpec& spec : rays) {
      const ind::Result ref = ind::independent_integral(kMLRef, kBox, tf, 0, spec.origin, spec.direction);
      const ReferenceResult r = integrate_reference(kML, kBox, tf, 0, make_ray(spec.origin, spec.direction), {kTol});
      // What the field resolves: its values' rounding, value_noise() ~ 2e-15 at fM = 6.
      check_tight({name, r.value, static_cast<double>(ref.value), r.error_estimate, kML.value_noise(), 1000,
                   r.evaluations, 600});
      EXPECT_TRUE(r.tolerance_met) << name;
    }
  }
}

TEST(ReferenceIntegratorTight, BoxOfOneE300) {
  // A box of +-1e300: positions there cannot resolve Marschner-Lobb (estimate 4.9e289 before,
  // then 2e300: the rest of the ray was bounded by max g x its length).  However long the rest,
  // it emits at most sup g / tau = 2 (the default transfer function): the estimate says so.
  const Box huge{Vec3(-1e300, -1e300, -1e300), Vec3(1e300, 1e300, 1e300)};
  const TransferFunction tf = tf_proportional();
  EXPECT_EQ(tf.max_emission_per_extinction(), 2);
  const ReferenceResult r = integrate_reference(kML, huge, tf, 0, make_ray({-2e300, 0.1, 0.2}, {1, 0, 0}), {kTol});
  EXPECT_TRUE(std::isfinite(r.value));
  EXPECT_FALSE(r.tolerance_met);
  EXPECT_LE(r.value - r.error_estimate, 0);
  EXPECT_GE(r.value + r.error_estimate, 2 - 1e-12);  // the true value lies in [0, 2]
  EXPECT_LE(r.error_estimate, 2 * (1 + 1e-15));
  // A ramp there is resolved (it is linear): I = 2 (1 - e^-Phi) = 2 with Phi ~ 1e300; the product
  // of a 1e300-long stretch and its field error overflowed and made the estimate NaN.
  const ReferenceResult s =
      integrate_reference(LinearRamp{{0.5, 0, 0}, 0.5}, huge, tf, 0, make_ray({-2e300, 0.1, 0.2}, {1, 0, 0}), {kTol});
  EXPECT_TRUE(s.tolerance_met);
  EXPECT_LE(std::abs(s.value - 2), s.error_estimate);
  EXPECT_LE(s.error_estimate, kTol);
}

}  // namespace
}  // namespace vrv
