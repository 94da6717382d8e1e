// The opacity-correction study's own computations (studies/opacity-correction/): group
// compositing, fit-error statistics, 8-bit groups, the Fig. 3 surfaces, pixel statistics, the
// render's sample groups, the N sweep's identities and thread independence, and the study file's
// one-line errors.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "lib/util/parallel.h"
#include "lib/reference_integrator.h"
#include "lib/order_estimate.h"
#include "studies/engine/study_rays.h"
#include "lib/study_file.h"
#include "studies/opacity-correction/opacity_correction.h"

namespace vrv {
namespace {

constexpr Correction kAll[] = {Correction::none, Correction::lacroute, Correction::schulze, Correction::lee_newman,
                               Correction::lee_newman_quadratic};

TEST(OpacityCorrectionStudy, CompositeGroupIsFrontToBackCompositing) {
  const std::vector<double> a{67.0 / 255, 69.2 / 255, 73.4 / 255, 78.6 / 255, 84.8 / 255};
  // Uncorrected: eqs. 1 and 3 written out.
  double T = 1, I = 0;
  for (double x : a) I += T * x * x, T *= 1 - x;
  const GroupResult none = composite_group(Correction::none, a, a, 5);
  EXPECT_NEAR(none.opacity, 1 - T, 1e-15);
  EXPECT_NEAR(none.intensity, I, 1e-15);
  EXPECT_EQ(none.p, 1);
  // Lee & Newman reproduces the unit sample's opacity; its p is the solver's.
  const GroupResult lee = composite_group(Correction::lee_newman, a, a, 5);
  EXPECT_NEAR(lee.opacity, a[0], 1e-15);
  EXPECT_EQ(lee.p, lee_newman_p(a, a[0]));
  EXPECT_LT(lee.opacity, none.opacity);
}

TEST(OpacityCorrectionStudy, NoCorrectionChangesAGroupOfOne) {
  for (Correction c : kAll)
    for (double x : {0.0, 0.2, 0.7, 1.0}) {
      const double g[1] = {x};
      const GroupResult r = composite_group(c, g, g, 1);
      EXPECT_EQ(r.opacity, x) << correction_name(c);
      EXPECT_EQ(r.intensity, x * x) << correction_name(c);
    }
}

TEST(OpacityCorrectionStudy, PairSurfaceHoldsTheTwoSampleFormulas) {
  const PairSurface none = pair_surface(Correction::none), lee = pair_surface(Correction::lee_newman),
                    lac = pair_surface(Correction::lacroute);
  ASSERT_EQ(none.opacity.size(), 65536u);
  for (int b = 0; b < 256; b += 17)
    for (int a = 0; a < 256; a += 15) {
      const double x = a / 255.0, y = b / 255.0;
      const int i = b * 256 + a;
      EXPECT_NEAR(none.intensity[i], x * x + (1 - x) * y * y, 1e-15);
      EXPECT_NEAR(lee.opacity[i], x, 1e-15);
      const double lx = lacroute(x, 2), ly = lacroute(y, 2);
      EXPECT_NEAR(lac.opacity[i], 1 - (1 - lx) * (1 - ly), 1e-15);
    }
  // The paper's reading of Fig. 3: a faint first and a dense second sample composite to less
  // intensity under the new correction than under the prior one.
  const int i = 255 * 256 + 10;  // a = 10, b = 255
  EXPECT_LT(lee.intensity[i], lac.intensity[i]);
}

TEST(OpacityCorrectionStudy, RandomByteGroupsAreDeterministicBytes) {
  const std::vector<double> g = random_byte_groups(5, 20000, 4), h = random_byte_groups(5, 20000, 4);
  ASSERT_EQ(g.size(), 100000u);
  EXPECT_EQ(g, h);
  EXPECT_NE(g, random_byte_groups(5, 20000, 5));
  std::vector<int> seen(256, 0);
  for (double x : g) {
    const double k = x * 255;
    ASSERT_EQ(k, std::round(k));
    ++seen[static_cast<int>(std::round(k))];
  }
  for (int k = 0; k < 256; ++k) EXPECT_GT(seen[k], 200) << k;  // ~390 expected each
}

TEST(OpacityCorrectionStudy, RampGroupsAreEveryPairsLinearRamp) {
  const std::vector<double> r = ramp_groups(5);
  ASSERT_EQ(r.size(), 65536u * 5);
  const std::size_t g = (10 * 256 + 200) * 5;  // D0 = 10, D1 = 200
  EXPECT_DOUBLE_EQ(r[g] * 255, 10);
  EXPECT_NEAR(r[g + 1] * 255, 10 + 190 / 5.0, 1e-12);
  EXPECT_NEAR(r[g + 4] * 255, 10 + 4 * 190 / 5.0, 1e-12);
}

TEST(OpacityCorrectionStudy, FitErrorStatisticsAreTheSampleMoments) {
  // N = 2: the fit is exact, every error is rounding.
  const FitErrorStats two = fit_error_stats(random_byte_groups(2, 5000, 1), 2, 0.1);
  EXPECT_EQ(two.groups, 5000);
  EXPECT_LT(two.max, 1e-12);
  EXPECT_EQ(two.fraction_above, 0);
  EXPECT_TRUE(two.all_in_unit);
  // N = 5: recompute the moments directly.
  const std::vector<double> g = random_byte_groups(5, 3000, 2);
  const FitErrorStats five = fit_error_stats(g, 5, 0.05);
  std::vector<double> e;
  for (std::size_t i = 0; i < g.size(); i += 5) {
    const std::span<const double> s(g.data() + i, 5);
    e.push_back(std::fabs(lee_newman_quadratic_p(s, s[0]) - lee_newman_p(s, s[0])));
  }
  double mean = 0, above = 0, mx = 0;
  for (double x : e) mean += x, above += x > 0.05, mx = std::max(mx, x);
  mean /= e.size();
  double var = 0;
  for (double x : e) var += (x - mean) * (x - mean);
  EXPECT_NEAR(five.mean, mean, 1e-15);
  EXPECT_NEAR(five.sd, std::sqrt(var / (e.size() - 1)), 1e-15);
  EXPECT_EQ(five.max, mx);
  EXPECT_DOUBLE_EQ(five.fraction_above, above / e.size());
  EXPECT_GT(five.mean, 1e-3);  // N = 5 is not exact: the statistic measures something
}

TEST(OpacityCorrectionStudy, PixelDifferenceIsMeanMaxRms) {
  const ErrorStats s = pixel_difference({0, 1, 2, 3}, {0, 0, 4, 3});
  EXPECT_DOUBLE_EQ(s.mean, 0.75);
  EXPECT_DOUBLE_EQ(s.max, 2);
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(5.0 / 4));
}

RenderScenes small_scenes() {
  RenderScenes s;
  s.analytic.box = Box{};
  s.analytic.field = MarschnerLobb{};
  s.analytic.transfer = TransferFunction::opacity_color(PiecewiseLinear({{0, 0}, {1, 0.999}}),
                                                        PiecewiseLinear({{0, 0}, {1, 1}}), 2.0 / 15);
  s.sampled = s.analytic;
  s.sampled.field = make_grid(Box{}, MarschnerLobb{}, {16, 16, 16}, GridLayout::node, Interpolation::trilinear);
  s.unit_step = 2.0 / 15;
  s.reference_tol = 1e-9;
  return s;
}

TEST(OpacityCorrectionStudy, RenderGroupsAreTheRaycastersFullGroups) {
  const RenderScenes s = small_scenes();
  Camera cam;
  cam.width = cam.height = 6;
  const int N = 5;
  const std::vector<double> g = render_groups(s, cam, N, false);
  long expected = 0;
  const DiscreteConfig config = oversampled_config(Correction::none, N, s.unit_step, false);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x) {
      const Ray ray = cam.ray(x, y);
      if (const auto iv = clip(ray, Box{})) {
        const long samples = discrete_raycast(s.sampled, ray, config).samples;
        expected += samples / N * N;
      }
    }
  EXPECT_EQ(static_cast<long>(g.size()), expected);
  EXPECT_GT(expected, 0);
  for (double a : g) EXPECT_TRUE(a >= 0 && a <= 0.999);
}

TEST(OpacityCorrectionStudy, SweepIsIdentityAtOneAndThreadIndependent) {
  const RenderScenes s = small_scenes();
  const std::vector<Ray> rays = study_rays(Box{}, 6, 3);
  const std::vector<Correction> cs(std::begin(kAll), std::end(kAll));
  std::vector<SweepRow> one, two;
  ReferenceAudit audit;
  {
    const ThreadLimit limit(1);
    one = error_against_N(s, rays, cs, {1, 4}, true, false, nullptr, audit);
  }
  {
    const ThreadLimit limit(2);
    two = error_against_N(s, rays, cs, {1, 4}, true, false, nullptr, audit);
  }
  EXPECT_EQ(audit.counts().rays, 2 * 6);  // each sweep's truth on every ray, counted
  ASSERT_EQ(one.size(), 10u);
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].mean_error, two[i].mean_error);
    EXPECT_TRUE(one[i].finite);
    if (one[i].N == 1) {
      EXPECT_EQ(one[i].max_diff_from_none, 0) << correction_name(one[i].correction);
    } else if (one[i].correction != Correction::none) {
      EXPECT_GT(one[i].max_diff_from_none, 0) << correction_name(one[i].correction);
    }
  }
}

TEST(OpacityCorrectionStudy, CentredOversamplesSplitTheUnitStepEvenly) {
  const SamplePlan plan{0.35, 0.1, 1.0, 7};  // unit samples at 0.35 .. 0.95, each for [t - 0.05, t + 0.05)
  const SamplePlan first = detail::oversampled(plan, 4), centred = detail::oversampled(plan, 4, true);
  EXPECT_EQ(first.t_first, plan.t_first);
  EXPECT_NEAR(centred.t_first, 0.3 + 0.0125, 1e-15);  // centre of the first quarter of [0.3, 0.4)
  EXPECT_DOUBLE_EQ(centred.dt, 0.025);
  EXPECT_EQ(centred.count, 28);  // up to 0.9875 < 1: 4 per unit step
  EXPECT_EQ(first.count, 26);    // 0.35 + 25 * 0.025 = 0.975 is the last below 1
  EXPECT_EQ(detail::oversampled(plan, 1, true).t_first, plan.t_first);
}

TEST(OpacityCorrectionStudy, CentredLacrouteConvergesAndFirstPlacementStalls) {
  // On a smooth ray through the analytic field, Lacroute with centred oversamples is the alpha
  // rule at step H/N with midpoint samples (second order); from the unit sample on, the samples
  // are (N - 1) H / (2N) late and the error stops falling.
  const RenderScenes s = small_scenes();
  const Ray ray{{-3, 0.1, 0.2}, Vec3(1, 0.05, -0.03).normalized()};
  const double I = integrate_reference(s.analytic, ray, {1e-12}).value;
  std::vector<double> centred, first;
  for (int N : {4, 8, 16, 32}) {
    centred.push_back(std::fabs(discrete_raycast(s.analytic, ray, oversampled_config(Correction::lacroute, N, s.unit_step, true)).value - I));
    first.push_back(std::fabs(discrete_raycast(s.analytic, ray, oversampled_config(Correction::lacroute, N, s.unit_step, false)).value - I));
  }
  EXPECT_NEAR(estimate_order({1.0 / 4, 1.0 / 8, 1.0 / 16, 1.0 / 32}, centred).order, 2, 0.3);
  EXPECT_GT(first.back(), 0.5 * first.front());
  EXPECT_GT(first.back(), 10 * centred.back());
}

std::string study_text() {
  std::ifstream in(std::filesystem::path(VRV_SOURCE_DIR) / "studies" / "opacity-correction" / "opacity-correction.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string parse_error(const std::string& text) {
  try {
    const toml::table doc = parse_study_toml(text, "oc.toml");
    const StudyReader reader("oc.toml");
    read_opacity_study(StudyInput{doc, reader, "oc"});
  } catch (const StudyFileError& e) {
    return e.what();
  }
  return "";
}

TEST(OpacityCorrectionStudy, StudyFileReadsAndBadKeysAreOneLineErrors) {
  const std::string text = study_text();
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(parse_error(text), "");
  const toml::table doc = parse_study_toml(text, "oc.toml");
  const StudyReader reader("oc.toml");
  const OpacityStudy s = read_opacity_study(StudyInput{doc, reader, "oc"});
  EXPECT_EQ(s.oversamples.size(), 5u);
  EXPECT_TRUE(std::holds_alternative<GridField>(s.scenes.sampled.field));
  EXPECT_EQ(s.sweep_N.front(), 1);

  std::string e = parse_error(text + "\nbogus = 1\n");
  EXPECT_NE(e.find("oc.toml"), std::string::npos) << e;
  EXPECT_NE(e.find("bogus"), std::string::npos) << e;
  e = parse_error(std::regex_replace(text, std::regex("\"lee_newman\", "), ""));
  EXPECT_NE(e.find("corrections"), std::string::npos) << e;
  e = parse_error(std::regex_replace(text, std::regex("N = \\[1, 2"), "N = [2, 2"));
  EXPECT_NE(e.find("sweep.N"), std::string::npos) << e;
  e = parse_error(std::regex_replace(text, std::regex("oversample = 5"), "oversample = 0"));
  EXPECT_NE(e.find("render.oversample"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
  // A grid of 64.5 nodes was read as 64: refused, naming the entry.
  e = parse_error(std::regex_replace(text, std::regex("resolution = \\[(\\d+),"), "resolution = [$1.5,"));
  EXPECT_NE(e.find("render.resolution[0]: expected a whole number, got "), std::string::npos) << e;
}

}  // namespace
}  // namespace vrv
