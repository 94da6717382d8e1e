#include "lib/sampling.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace vrv {
namespace {

const Box cube{Vec3(-1, -1, -1), Vec3(1, 1, 1)};
constexpr double kTol = 1e-12;

SamplingConfig rate_config(Strategy s, double rate, std::array<int, 3> dims = {4, 4, 4}) {
  SamplingConfig c;
  c.strategy = s;
  c.rate = rate;
  c.dims = dims;
  return c;
}

SamplingConfig step_config(Strategy s, double step) {
  SamplingConfig c;
  c.strategy = s;
  c.step = step;
  return c;
}

struct Planned {
  Ray ray;
  Interval iv;
  SamplePlan plan;
};

Planned plan_for(const SamplingConfig& c, const Vec3& origin, const Vec3& dir,
                 const Box& box = cube) {
  const Ray ray = make_ray(origin, dir);
  const auto iv = clip(ray, box);
  EXPECT_TRUE(iv.has_value());
  return Planned{ray, *iv, plan_samples(c, ray, *iv, box)};
}

// The x coordinates of all samples of a ray along +x.
std::vector<double> xs(const Planned& p) {
  std::vector<double> out;
  for (long k = 0; k < p.plan.count; ++k) out.push_back(p.ray.at(p.plan.t(k)).x());
  return out;
}

void expect_xs(const Planned& p, const std::vector<double>& want) {
  const auto got = xs(p);
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], kTol) << "sample " << i;
}

// The count agrees with the loop predicate t(k) < t_end, evaluated as SamplePlan::t does.
void expect_consistent(const SamplePlan& p) {
  ASSERT_GE(p.count, 0);
  ASSERT_TRUE(std::isfinite(p.t_first));
  ASSERT_TRUE(std::isfinite(p.dt));
  ASSERT_TRUE(std::isfinite(p.t_end));
  ASSERT_GE(p.dt, 0);
  if (p.count > 0) {
    EXPECT_GT(p.dt, 0);
    EXPECT_LT(p.t(p.count - 1), p.t_end);
  }
  EXPECT_GE(p.t(p.count), p.t_end);
  long loop = 0;
  while (p.t(loop) < p.t_end && loop <= p.count) ++loop;
  EXPECT_EQ(loop, p.count);
}

const Vec3 kX(1, 0, 0);
const Vec3 kFromLeft(-3, 0, 0);  // enters [-1,1]^3 at t0 = 2, leaves at t1 = 4

// ---------------------------------------------------------------- names

TEST(Sampling, NamesRoundTrip) {
  for (Strategy s : {Strategy::eye, Strategy::entry, Strategy::entry_exit,
                     Strategy::entry_exit_corner, Strategy::step, Strategy::vtk,
                     Strategy::inviwo, Strategy::partial, Strategy::exit_anchored}) {
    const auto parsed = parse_strategy(strategy_name(s));
    ASSERT_TRUE(parsed) << strategy_name(s);
    EXPECT_EQ(*parsed, s);
  }
  EXPECT_EQ(strategy_name(Strategy::entry_exit_corner), "entry_exit_corner");
  EXPECT_FALSE(parse_strategy("Entry"));
  EXPECT_FALSE(parse_strategy("entry-exit"));
  EXPECT_FALSE(parse_strategy(""));
}

// ---------------------------------------------------------------- worked examples, +x ray

TEST(Sampling, EntryRateOneGivesFourVoxelMidpoints) {
  // tex ray (1,0,0), ray*dim = (4,0,0): 4 samples, tIncr = 1/4 tex = 0.5 world, tStart = 1/8 tex.
  const auto p = plan_for(rate_config(Strategy::entry, 1), kFromLeft, kX);
  EXPECT_DOUBLE_EQ(p.plan.dt, 0.5);
  EXPECT_DOUBLE_EQ(p.plan.t_first, 2.25);
  EXPECT_DOUBLE_EQ(p.plan.t_end, 4);
  expect_xs(p, {-0.75, -0.25, 0.25, 0.75});
  expect_consistent(p.plan);
}

TEST(Sampling, EntryNonIntegerRateMissesPartOfTheBack) {
  // samples = 4 * 1.3 = 5.2 (not floored): dt = 2/5.2, samples at -1 + (k + 1/2) dt while < 1,
  // i.e. k + 1/2 < 5.2: five samples covering 5 dt; the last 0.2 dt before the exit is missed.
  const auto p = plan_for(rate_config(Strategy::entry, 1.3), kFromLeft, kX);
  const double dt = 2 / 5.2;
  EXPECT_NEAR(p.plan.dt, dt, kTol);
  std::vector<double> want;
  for (int k = 0; k < 5; ++k) want.push_back(-1 + (k + 0.5) * dt);
  expect_xs(p, want);
  EXPECT_NEAR(1 - (want.back() + dt / 2), 0.2 * dt, kTol);  // uncovered stretch at the exit
  expect_consistent(p.plan);
}

TEST(Sampling, EntryExitFloorsTheCount) {
  // floor(5.2) = 5 samples of dt = 0.4, half a step inside both ends.
  const auto p = plan_for(rate_config(Strategy::entry_exit, 1.3), kFromLeft, kX);
  EXPECT_NEAR(p.plan.dt, 0.4, kTol);
  expect_xs(p, {-0.8, -0.4, 0, 0.4, 0.8});
  expect_consistent(p.plan);
  // Rate 1: same as entry (4 samples, integer).
  expect_xs(plan_for(rate_config(Strategy::entry_exit, 1), kFromLeft, kX),
            {-0.75, -0.25, 0.25, 0.75});
}

TEST(Sampling, EntryExitCornerUsesDimsMinusOne) {
  // ceil(1 * |(1,0,0) * (3,3,3)|) = 3 samples, dt = 2/3, at the midpoints.
  const auto p = plan_for(rate_config(Strategy::entry_exit_corner, 1), kFromLeft, kX);
  EXPECT_NEAR(p.plan.dt, 2.0 / 3, kTol);
  expect_xs(p, {-2.0 / 3, 0, 2.0 / 3});
  expect_consistent(p.plan);
  // Rate 1.3: ceil(3.9) = 4 samples of 0.5.
  expect_xs(plan_for(rate_config(Strategy::entry_exit_corner, 1.3), kFromLeft, kX),
            {-0.75, -0.25, 0.25, 0.75});
}

TEST(Sampling, EyeAlignedFromTheRayOrigin) {
  // Eye (-3,0,0) -> tex (-1,.5,.5), entry tex (0,.5,.5): distance 1 = 4 tIncr exactly,
  // fract = 0 so tStart = tIncr (the entry itself is not sampled): x = -0.5, 0, 0.5; the next one
  // would sit exactly on the exit (t = 4), which is not < tEnd.
  const auto p = plan_for(rate_config(Strategy::eye, 1), kFromLeft, kX);
  EXPECT_DOUBLE_EQ(p.plan.dt, 0.5);
  expect_xs(p, {-0.5, 0, 0.5});
  expect_consistent(p.plan);

  // Eye 0.9 world (0.45 tex = 1.8 tIncr) before the entry: tStart = 0.2 tIncr = 0.1 world.
  const auto q = plan_for(rate_config(Strategy::eye, 1), Vec3(-1.9, 0, 0), kX);
  expect_xs(q, {-0.9, -0.4, 0.1, 0.6});
  expect_consistent(q.plan);
}

TEST(Sampling, StepWorkedExample) {
  // H = 0.3, first at -1 + 0.15.
  const auto p = plan_for(step_config(Strategy::step, 0.3), kFromLeft, kX);
  expect_xs(p, {-0.85, -0.55, -0.25, 0.05, 0.35, 0.65, 0.95});
  expect_consistent(p.plan);
}

TEST(Sampling, VtkFirstSampleOneFullStepInsideAndExitInclusive) {
  const auto p = plan_for(step_config(Strategy::vtk, 0.3), kFromLeft, kX);
  expect_xs(p, {-0.7, -0.4, -0.1, 0.2, 0.5, 0.8});  // [0.8, 1] (a partial step) is dropped
  expect_consistent(p.plan);
  // H = 0.5: the fourth sample lies exactly on the exit face and is kept (t <= t1).
  const auto q = plan_for(step_config(Strategy::vtk, 0.5), kFromLeft, kX);
  expect_xs(q, {-0.5, 0, 0.5, 1});
  EXPECT_EQ(q.plan.t_end, std::nextafter(4.0, 5.0));
  expect_consistent(q.plan);
  // A chord shorter than one step gets nothing.
  EXPECT_EQ(plan_for(step_config(Strategy::vtk, 3), kFromLeft, kX).plan.count, 0);
}

TEST(Sampling, InviwoRoundsToAWholeNumberOfSteps) {
  // L = 2: H = 0.45 -> round(4.44) = 4 steps of 0.5; H = 0.3 -> round(6.67) = 7 steps of 2/7;
  // H = 5 -> max(1, round(0.4)) = 1 step: one sample at the midpoint.
  expect_xs(plan_for(step_config(Strategy::inviwo, 0.45), kFromLeft, kX),
            {-0.75, -0.25, 0.25, 0.75});
  const auto p = plan_for(step_config(Strategy::inviwo, 0.3), kFromLeft, kX);
  EXPECT_EQ(p.plan.count, 7);
  EXPECT_NEAR(p.plan.dt, 2.0 / 7, kTol);
  EXPECT_NEAR(xs(p).front(), -1 + 1.0 / 7, kTol);
  EXPECT_NEAR(xs(p).back(), 1 - 1.0 / 7, kTol);
  expect_consistent(p.plan);
  expect_xs(plan_for(step_config(Strategy::inviwo, 5), kFromLeft, kX), {0});
}

// ---------------------------------------------------------------- texture space

TEST(Sampling, RateIsPerVoxelInTextureSpaceOfAnAnisotropicBox) {
  // Box 4 x 1 x 1 with 8 x 2 x 2 voxels: every voxel is 0.5 world wide.
  const Box box{Vec3(0, 0, 0), Vec3(4, 1, 1)};
  const auto cfg = rate_config(Strategy::entry, 1, {8, 2, 2});
  const auto along_x = plan_for(cfg, Vec3(-1, 0.5, 0.5), Vec3(1, 0, 0), box);
  EXPECT_EQ(along_x.plan.count, 8);
  EXPECT_NEAR(along_x.plan.dt, 0.5, kTol);
  const auto along_y = plan_for(cfg, Vec3(1, -1, 0.5), Vec3(0, 1, 0), box);
  EXPECT_EQ(along_y.plan.count, 2);
  EXPECT_NEAR(along_y.plan.dt, 0.5, kTol);
  EXPECT_NEAR(along_y.ray.at(along_y.plan.t(0)).y(), 0.25, kTol);
  // Corner strategy: dims - 1 = (7, 1, 1): along x ceil(7) = 7, along y ceil(1) = 1.
  const auto corner = rate_config(Strategy::entry_exit_corner, 1, {8, 2, 2});
  EXPECT_EQ(plan_for(corner, Vec3(-1, 0.5, 0.5), Vec3(1, 0, 0), box).plan.count, 7);
  EXPECT_EQ(plan_for(corner, Vec3(1, -1, 0.5), Vec3(0, 1, 0), box).plan.count, 1);
}

TEST(Sampling, DiagonalRay) {
  // Through the cube's main diagonal: world length 2 sqrt 3, tex ray (1,1,1), ray*dim = (4,4,4).
  const Vec3 o(-2, -2, -2), d(1, 1, 1);
  const double L = 2 * std::sqrt(3.0);
  const double s = 4 * std::sqrt(3.0);  // 6.93 samples

  const auto entry = plan_for(rate_config(Strategy::entry, 1), o, d);
  EXPECT_NEAR(entry.iv.length(), L, kTol);
  EXPECT_NEAR(entry.plan.dt, L / s, kTol);  // = 0.5 world: isotropic voxels
  EXPECT_NEAR(entry.plan.dt, 0.5, kTol);
  EXPECT_EQ(entry.plan.count, 7);           // k + 1/2 < 6.93
  expect_consistent(entry.plan);

  const auto ee = plan_for(rate_config(Strategy::entry_exit, 1), o, d);
  EXPECT_EQ(ee.plan.count, 6);  // floor(6.93)
  EXPECT_NEAR(ee.plan.dt, L / 6, kTol);
  const Vec3 first = ee.ray.at(ee.plan.t(0));
  const Vec3 last = ee.ray.at(ee.plan.t(ee.plan.count - 1));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(first[a], -1 + 1.0 / 6, kTol);  // half of a sixth of the diagonal inside
    EXPECT_NEAR(last[a], 1 - 1.0 / 6, kTol);
  }

  const auto corner = plan_for(rate_config(Strategy::entry_exit_corner, 1), o, d);
  EXPECT_EQ(corner.plan.count, 6);  // ceil(|(3,3,3)|) = ceil(5.196)
  EXPECT_NEAR(corner.plan.dt, L / 6, kTol);
}

// ---------------------------------------------------------------- eye alignment

TEST(Sampling, EyeParallelRaysAtTheSameDistanceShareThePhase) {
  const auto cfg = rate_config(Strategy::eye, 1.7);
  const auto a = plan_for(cfg, Vec3(-2.37, 0.1, -0.3), kX);
  const auto b = plan_for(cfg, Vec3(-2.37, -0.8, 0.65), kX);
  EXPECT_DOUBLE_EQ(a.plan.t_first, b.plan.t_first);
  EXPECT_DOUBLE_EQ(a.plan.dt, b.plan.dt);
  EXPECT_EQ(a.plan.count, b.plan.count);
}

TEST(Sampling, EyeSamplesLieOnSpheresAroundTheEye) {
  // Per ray, in texture space: tStart + |entry - eye| is a whole number of tIncr.  In the cube
  // with equal dims tIncr is the same for every direction (world 1 / (2 rate)), so all samples of
  // all rays from one eye lie on the spheres |p - eye| = m * dt.
  const Vec3 eye(-2.5, 0.3, 0.2);
  const std::array<Box, 2> boxes{cube, Box{Vec3(0, -1, -1), Vec3(1, 2, 0.5)}};
  for (size_t b = 0; b < boxes.size(); ++b) {
    const Box& box = boxes[b];
    const auto cfg = rate_config(Strategy::eye, 1.3, {5, 7, 3});
    const auto iso = rate_config(Strategy::eye, 1.3, {6, 6, 6});
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    int hits = 0;
    for (int i = 0; i < 200; ++i) {
      const Vec3 target(box.min + (box.max - box.min).cwiseProduct(
                                      Vec3(u(rng), u(rng), u(rng)) * 0.5 + Vec3::Constant(0.5)));
      const Ray ray = make_ray(eye, target - eye);
      const auto iv = clip(ray, box);
      if (!iv || iv->length() == 0) continue;
      ++hits;
      const Vec3 ext = box.extent();
      auto tex = [&](const Vec3& p) { return Vec3((p - box.min).cwiseQuotient(ext)); };
      const double scale = iv->length() / (tex(ray.at(iv->t1)) - tex(ray.at(iv->t0))).norm();

      const SamplePlan p = plan_samples(cfg, ray, *iv, box);
      expect_consistent(p);
      const double t_start_tex = (p.t_first - iv->t0) / scale;
      const double t_incr_tex = p.dt / scale;
      const double entry_dist = (tex(ray.at(iv->t0)) - tex(eye)).norm();
      const double m = (t_start_tex + entry_dist) / t_incr_tex;
      EXPECT_NEAR(m, std::round(m), 1e-8) << "ray " << i;
      EXPECT_GT(p.t_first, iv->t0);
      EXPECT_LE(p.t_first, iv->t0 + p.dt * (1 + 1e-12));

      if (b == 0) {
        const SamplePlan q = plan_samples(iso, ray, *iv, box);
        EXPECT_NEAR(q.dt, 2 / (6 * 1.3), 1e-12);  // voxel width 2/6 over the rate
        for (long k = 0; k < q.count; ++k) {
          const double r = (ray.at(q.t(k)) - eye).norm() / q.dt;
          EXPECT_NEAR(r, std::round(r), 1e-8);
        }
      }
    }
    EXPECT_GT(hits, 150);
  }
}

TEST(Sampling, EyeOptionOverridesTheRayOrigin) {
  // A ray starting part-way to the box, told where the eye is, samples where the eye's ray does.
  auto cfg = rate_config(Strategy::eye, 1.3);
  const Vec3 eye(-2.6, 0.2, 0.1), d = Vec3(1, 0.2, -0.1).normalized();
  const auto from_eye = plan_for(cfg, eye, d);
  cfg.eye = eye;
  const auto later = plan_for(cfg, eye + 0.77 * d, d);
  ASSERT_EQ(from_eye.plan.count, later.plan.count);
  for (long k = 0; k < later.plan.count; ++k) {
    EXPECT_LT((from_eye.ray.at(from_eye.plan.t(k)) - later.ray.at(later.plan.t(k))).norm(), 1e-12);
  }
}

// ---------------------------------------------------------------- corners and degenerate rays

TEST(Sampling, EntryExitDropsACornerChordThatEntryExitCornerKeeps) {
  // In the z = 0 plane, the line x + y = 1.9 cuts the corner (1,1): chord from (0.9,1) to
  // (1,0.9), world length 0.1 sqrt 2; in texture space 0.0707, times dim 4: 0.28 samples.
  const Vec3 mid(0.95, 0.95, 0);
  const Vec3 d(1, -1, 0);
  const Vec3 o = mid - 3 * d;
  const auto ee = plan_for(rate_config(Strategy::entry_exit, 1), o, d);
  EXPECT_NEAR(ee.iv.length(), 0.1 * std::sqrt(2.0), 1e-12);
  EXPECT_EQ(ee.plan.count, 0);  // floor(0.28) = 0: the published behaviour
  expect_consistent(ee.plan);

  const auto corner = plan_for(rate_config(Strategy::entry_exit_corner, 1), o, d);
  ASSERT_EQ(corner.plan.count, 1);  // ceil(0.21) = 1
  EXPECT_NEAR(corner.plan.dt, corner.iv.length(), 1e-15);
  EXPECT_LT((corner.ray.at(corner.plan.t(0)) - mid).norm(), 1e-12);  // the chord midpoint
  expect_consistent(corner.plan);

  // Entry (not floored): tStart = tIncr / 2 lies beyond the chord, so nothing either.
  EXPECT_EQ(plan_for(rate_config(Strategy::entry, 1), o, d).plan.count, 0);
  // Inviwo keeps at least one step: the midpoint.
  const auto inv = plan_for(step_config(Strategy::inviwo, 0.5), o, d);
  ASSERT_EQ(inv.plan.count, 1);
  EXPECT_LT((inv.ray.at(inv.plan.t(0)) - mid).norm(), 1e-12);
}

TEST(Sampling, ZeroLengthRaysHaveNoSamplesAndNoNaN) {
  // A ray grazing the corner (1,1,z) of the cube: a zero-length chord.
  const Ray graze = make_ray(Vec3(0, 2, 0), Vec3(1, -1, 0));
  const auto iv = clip(graze, cube);
  ASSERT_TRUE(iv);
  EXPECT_EQ(iv->length(), 0);
  std::vector<SamplingConfig> configs;
  for (Strategy s : {Strategy::eye, Strategy::entry, Strategy::entry_exit,
                     Strategy::entry_exit_corner}) {
    configs.push_back(rate_config(s, 2.5));
  }
  for (Strategy s : {Strategy::step, Strategy::vtk, Strategy::inviwo, Strategy::partial, Strategy::exit_anchored}) {
    configs.push_back(step_config(s, 0.1));
  }
  for (const auto& c : configs) {
    for (const Interval& i : {*iv, Interval{1.5, 1.5}, Interval{0, 0}}) {
      const SamplePlan p = plan_samples(c, graze, i, cube);
      EXPECT_EQ(p.count, 0) << strategy_name(c.strategy);
      expect_consistent(p);
    }
  }
}

TEST(Sampling, SingleVoxelGridCornerStrategyHasNoSamples) {
  // dims - 1 = 0: ceil(rate * 0) = 0 samples; no division by zero leaks out.
  const auto p = plan_for(rate_config(Strategy::entry_exit_corner, 1, {1, 1, 1}), kFromLeft, kX);
  EXPECT_EQ(p.plan.count, 0);
  expect_consistent(p.plan);
}

TEST(Sampling, PartialStepSampledAtItsOwnMidpointAtTheExitOrTheEntry) {
  // Chord [2, 4], step 0.75: two whole steps and a partial one of 0.5.
  const auto at_exit = plan_for(step_config(Strategy::partial, 0.75), kFromLeft, kX).plan;
  EXPECT_EQ(at_exit.count, 2);
  EXPECT_DOUBLE_EQ(at_exit.t(0), 2.375);
  EXPECT_DOUBLE_EQ(at_exit.t(1), 3.125);
  EXPECT_DOUBLE_EQ(at_exit.partial, 0.5);
  EXPECT_DOUBLE_EQ(at_exit.t_partial, 3.75);
  EXPECT_FALSE(at_exit.partial_first);
  const auto from_exit = plan_for(step_config(Strategy::exit_anchored, 0.75), kFromLeft, kX).plan;
  EXPECT_EQ(from_exit.count, 2);
  EXPECT_DOUBLE_EQ(from_exit.t_partial, 2.25);
  EXPECT_TRUE(from_exit.partial_first);
  EXPECT_DOUBLE_EQ(from_exit.t(0), 2.875);
  EXPECT_DOUBLE_EQ(from_exit.t(1), 3.625);
  // A chord shorter than the step: the partial sample alone.
  const auto short_chord = plan_for(step_config(Strategy::partial, 3), kFromLeft, kX).plan;
  EXPECT_EQ(short_chord.count, 0);
  EXPECT_DOUBLE_EQ(short_chord.partial, 2);
  EXPECT_DOUBLE_EQ(short_chord.t_partial, 3);
}

// ---------------------------------------------------------------- the loop predicate

TEST(Sampling, CountsAgreeWithTheLoopPredicateOnRandomRays) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_real_distribution<double> rate(0.05, 5);
  std::uniform_real_distribution<double> step(0.001, 1.5);
  const Box box{Vec3(-1, -0.5, 0), Vec3(2, 1, 0.7)};
  int checked = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 o = Vec3(u(rng), u(rng), u(rng)) * 4;
    const Vec3 target = box.min + (box.max - box.min).cwiseProduct(
                                      Vec3(u(rng), u(rng), u(rng)) * 0.5 + Vec3::Constant(0.5));
    if ((target - o).norm() == 0) continue;
    const Ray ray = make_ray(o, target - o);
    const auto iv = clip(ray, box);
    if (!iv) continue;
    const auto dims = std::array<int, 3>{1 + int(rng() % 40), 1 + int(rng() % 40), 1 + int(rng() % 40)};
    for (Strategy s : {Strategy::eye, Strategy::entry, Strategy::entry_exit,
                       Strategy::entry_exit_corner}) {
      const SamplePlan p = plan_samples(rate_config(s, rate(rng), dims), ray, *iv, box);
      expect_consistent(p);
      if (p.count > 0) {
        EXPECT_GT(p.t_first, iv->t0);
        EXPECT_EQ(p.t_end, iv->t1);
      }
      if ((s == Strategy::entry_exit || s == Strategy::entry_exit_corner) && p.count > 0) {
        // Midpoints of a whole number of equal steps that tile the chord.
        EXPECT_NEAR(p.count * p.dt, iv->length(), 1e-12 * (1 + iv->length()));
        EXPECT_NEAR(p.t(0) - iv->t0, p.dt / 2, 1e-12);
        EXPECT_NEAR(iv->t1 - p.t(p.count - 1), p.dt / 2, 1e-12);
      }
      ++checked;
    }
    for (Strategy s : {Strategy::step, Strategy::vtk, Strategy::inviwo, Strategy::partial, Strategy::exit_anchored}) {
      const SamplePlan p = plan_samples(step_config(s, step(rng)), ray, *iv, box);
      expect_consistent(p);
      if (s == Strategy::inviwo && iv->length() > 0) {
        EXPECT_GE(p.count, 1);
        EXPECT_NEAR(p.count * p.dt, iv->length(), 1e-12 * (1 + iv->length()));
      }
      if (s == Strategy::partial || s == Strategy::exit_anchored) {
        // Whole steps at their midpoints and the partial step at its own tile the chord.
        EXPECT_NEAR(p.count * p.dt + p.partial, iv->length(), 1e-12 * (1 + iv->length()));
        EXPECT_GE(p.partial, 0);
        if (p.partial > 0) {
          const double from = s == Strategy::partial ? iv->t1 - p.partial : iv->t0;
          EXPECT_NEAR(p.t_partial, from + p.partial / 2, 1e-12 * (1 + std::abs(from)));
        }
        if (p.count > 0) {
          const double start = s == Strategy::partial ? iv->t0 : iv->t0 + p.partial;
          EXPECT_NEAR(p.t(0) - start, p.dt / 2, 1e-12 * (1 + std::abs(start)));
        }
      }
      if (s == Strategy::vtk && p.count > 0) {
        EXPECT_LE(p.t(p.count - 1), iv->t1);
        EXPECT_GT(p.t(p.count), iv->t1);
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

// ---------------------------------------------------------------- bad input

TEST(Sampling, BadRateOrStepThrows) {
  const Ray ray = make_ray(kFromLeft, kX);
  const Interval iv{2, 4};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (Strategy s : {Strategy::eye, Strategy::entry, Strategy::entry_exit,
                     Strategy::entry_exit_corner}) {
    for (double r : {0.0, -1.0, nan, inf, -inf}) {
      try {
        plan_samples(rate_config(s, r), ray, iv, cube);
        ADD_FAILURE() << strategy_name(s) << " accepted rate " << r;
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("--rate"), std::string::npos) << e.what();
      }
    }
    auto c = rate_config(s, 1);
    c.step = -1;  // ignored by rate-based strategies
    EXPECT_NO_THROW(plan_samples(c, ray, iv, cube));
  }
  for (Strategy s : {Strategy::step, Strategy::vtk, Strategy::inviwo, Strategy::partial, Strategy::exit_anchored}) {
    for (double h : {0.0, -0.5, nan, inf}) {
      try {
        plan_samples(step_config(s, h), ray, iv, cube);
        ADD_FAILURE() << strategy_name(s) << " accepted step " << h;
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("--step"), std::string::npos) << e.what();
      }
    }
    auto c = step_config(s, 0.5);
    c.rate = 0;  // ignored by step-based strategies
    EXPECT_NO_THROW(plan_samples(c, ray, iv, cube));
  }
  // Bad rates throw even for a degenerate chord (a configuration error, not a ray property).
  EXPECT_THROW(plan_samples(rate_config(Strategy::entry, 0), ray, Interval{2, 2}, cube),
               std::invalid_argument);
  // Absurd sample counts and bad grids are refused rather than looped over.
  EXPECT_THROW(plan_samples(step_config(Strategy::step, 1e-13), ray, iv, cube),
               std::invalid_argument);
  EXPECT_THROW(plan_samples(rate_config(Strategy::entry, 1, {0, 4, 4}), ray, iv, cube),
               std::invalid_argument);
}

}  // namespace
}  // namespace vrv
