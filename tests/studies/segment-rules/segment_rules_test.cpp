// The segment-rules study's own computations: zeta and Psi of a unit segment for linear opacity,
// linear extinction and the average-opacity approximation; the image-error run.
#include "studies/segment-rules/segment_rules.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <limits>
#include <random>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>

#include "lib/util/parallel.h"
#include "lib/scene_file.h"
#include "lib/study_file.h"
#include "studies/engine/study_driver.h"

namespace vrv {
namespace {

TEST(SegmentRules, MeanLogMatchesTheDividedDifferenceAndItsLimits) {
  // (b ln b - a ln a)/(b - a) - 1 where that has no cancellation.
  for (auto [a, b] : {std::pair{0.2, 0.9}, {1.0, 0.001}, {0.5, 0.25}}) {
    const double direct = (b * std::log(b) - a * std::log(a)) / (b - a) - 1;
    EXPECT_NEAR(mean_log(a, b), direct, 1e-15);
    EXPECT_EQ(mean_log(a, b), mean_log(b, a));
  }
  EXPECT_EQ(mean_log(0.3, 0.3), std::log(0.3));
  EXPECT_NEAR(mean_log(0.3, 0.3 * (1 + 1e-12)), std::log(0.3) + 0.5e-12, 4e-16);  // 2 ulp
  EXPECT_EQ(mean_log(0.0, 0.7), std::log(0.7) - 1);
  EXPECT_EQ(mean_log(0.0, 0.0), -std::numeric_limits<double>::infinity());
}

// alpha from 0 to 1 (the back fully opaque): int_0^1 ln(1 - s) ds = -1, so zeta = 1/e, and
// Phi(s) = s + (1 - s) ln(1 - s).
TEST(SegmentRules, LinearAlphaIsFiniteAndExactWithAnOpaqueBack) {
  const ZetaPsi v = linear_alpha_segment(0.0, 1.0);
  EXPECT_NEAR(v.zeta, std::exp(-1.0), 1e-16);
  const double psi = boost::math::quadrature::gauss_kronrod<double, 61>::integrate(
      [](double s) { return s < 1 ? std::exp(-s - (1 - s) * std::log1p(-s)) : std::exp(-1.0); }, 0.0, 1.0, 15,
      1e-14);
  EXPECT_NEAR(v.psi, psi, 1e-13);
  // Reversed: an opaque point at the front blocks nothing (it has no width); zeta is symmetric.
  EXPECT_NEAR(linear_alpha_segment(1.0, 0.0).zeta, std::exp(-1.0), 1e-16);
  const ZetaPsi opaque = linear_alpha_segment(1.0, 1.0);
  EXPECT_EQ(opaque.zeta, 0.0);
  EXPECT_EQ(opaque.psi, 0.0);
}

TEST(SegmentRules, ExactModelsAgreeWithNestedQuadrature) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> alpha(0.0, 0.999);
  for (int i = 0; i < 50; ++i) {
    const double f = alpha(rng), b = alpha(rng);
    const ZetaPsi a = linear_alpha_segment(f, b), qa = linear_alpha_by_quadrature(f, b);
    EXPECT_NEAR(a.zeta, qa.zeta, 1e-13) << f << " " << b;
    EXPECT_NEAR(a.psi, qa.psi, 1e-13) << f << " " << b;
    const ZetaPsi t = linear_tau_segment(f, b), qt = linear_tau_by_quadrature(f, b);
    EXPECT_NEAR(t.zeta, qt.zeta, 1e-13) << f << " " << b;
    EXPECT_NEAR(t.psi, qt.psi, 1e-13) << f << " " << b;
  }
}

// A homogeneous segment: every model is the constant-tau one, zeta = 1 - alpha,
// Psi = alpha / tau.
TEST(SegmentRules, AllModelsAgreeOnAHomogeneousSegment) {
  for (double a : {0.0, 1e-9, 0.05, 0.5, 0.9, 0.999}) {
    const double tau = -std::log1p(-a);
    const double psi = a == 0 ? 1.0 : a / tau;
    for (const ZetaPsi& v : {linear_alpha_segment(a, a), linear_tau_segment(a, a), average_opacity_segment(a, a)}) {
      EXPECT_NEAR(v.zeta, 1 - a, 2e-16) << a;
      EXPECT_NEAR(v.psi, psi, 4e-16) << a;
    }
  }
}

TEST(SegmentRules, AverageOpacityIsMorelandsFormula) {
  for (auto [f, b] : {std::pair{0.1, 0.7}, {0.0, 0.999}, {0.6, 0.2}}) {
    const ZetaPsi v = average_opacity_segment(f, b);
    const double mean = 0.5 * (f + b);
    EXPECT_NEAR(v.zeta, 1 - mean, 1e-16);
    EXPECT_NEAR(v.psi, mean / -std::log1p(-mean), 1e-15);
    EXPECT_EQ(v.psi, average_opacity_segment(b, f).psi);  // only the mean enters
  }
  const ZetaPsi opaque = average_opacity_segment(1.0, 1.0);
  EXPECT_EQ(opaque.zeta, 0.0);
  EXPECT_EQ(opaque.psi, 0.0);
}

// The exact zeta of both models is a geometric-type mean of the transparencies 1 - alpha, the
// approximation their arithmetic mean: the approximation never under-estimates zeta.
TEST(SegmentRules, AverageOpacityNeverUnderestimatesZeta) {
  for (double f : opacity_grid(11, 0.999))
    for (double b : opacity_grid(11, 0.999)) {
      const double avg = average_opacity_segment(f, b).zeta;
      EXPECT_GE(avg, linear_alpha_segment(f, b).zeta - 1e-16) << f << " " << b;
      EXPECT_GE(avg, linear_tau_segment(f, b).zeta - 1e-16) << f << " " << b;
      EXPECT_NEAR(linear_tau_segment(f, b).zeta, std::sqrt((1 - f) * (1 - b)), 1e-15);
    }
}

// Psi weighs the front: with the opaque end at the back more of the segment is seen.
TEST(SegmentRules, PsiIsLargerWithTheOpacityAtTheBack) {
  for (const auto& model : {linear_alpha_segment, linear_tau_segment}) {
    EXPECT_GT(model(0.1, 0.9).psi, model(0.9, 0.1).psi);
    EXPECT_NEAR(model(0.1, 0.9).zeta, model(0.9, 0.1).zeta, 1e-15);
  }
}

TEST(SegmentRules, OpacityGridEndsBelowOne) {
  const std::vector<double> g = opacity_grid(21, 0.9990234375);
  ASSERT_EQ(g.size(), 21u);
  EXPECT_EQ(g.front(), 0.0);
  EXPECT_EQ(g[10], 0.5);
  EXPECT_EQ(g.back(), 0.9990234375);
}

RenderSpec tiny_render() {
  RenderSpec s;
  s.name = "tiny";
  s.scene = parse_scene(
      "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
      "[field]\nkind = \"marschner_lobb\"\nfM = 2.0\nalpha = 0.25\n"
      "[transfer]\nemission = [[-1, 1.5], [2, 0]]\nextinction = [[-1, 0.1], [2, 2.5]]\n"
      "[camera]\nprojection = \"perspective\"\neye = [0, -1.5, -5.5]\ntarget = [0, 0, 0]\nfov = 30.0\n"
      "width = 8\nheight = 8\n",
      "tiny");
  s.steps = s.quick_steps = {0.04, 0.02, 0.01};
  s.map_step = 0.02;
  s.quick_width = s.quick_height = 8;
  return s;
}

TEST(SegmentRules, RenderErrorsShrinkAtTheExpectedOrdersAndDoNotDependOnThreads) {
  const std::vector<RuleSpec> rules{{SegmentRule::riemann, 1}, {SegmentRule::moreland, 2}};
  RenderResult one, two;
  ReferenceAudit audit;
  {
    const ThreadLimit limit(1);
    one = run_render(tiny_render(), rules, Strategy::inviwo, 1e-12, audit, true, false);
  }
  {
    const ThreadLimit limit(2);
    two = run_render(tiny_render(), rules, Strategy::inviwo, 1e-12, audit, true, false);
  }
  ASSERT_EQ(one.rows.size(), 6u);
  EXPECT_GT(one.hit_pixels, 0);
  // Both renders' reference pixels were counted, none missed.
  EXPECT_EQ(audit.counts().rays, 2L * 8 * 8);
  EXPECT_EQ(audit.counts().missed, 0);
  for (std::size_t i = 0; i < one.rows.size(); ++i) {
    EXPECT_EQ(one.rows[i].mean_error, two.rows[i].mean_error);
    EXPECT_EQ(one.rows[i].max_error, two.rows[i].max_error);
  }
  EXPECT_EQ(one.error_maps[1].pixels, two.error_maps[1].pixels);
  // The tolerance derived from each fit's spread (lib/order_estimate.h), the study file's margin and floor.
  const OrderTolerance tol{2, 0.05};
  EXPECT_TRUE(order_matches(one.fits[0], 1, tol)) << one.fits[0].order << " +- " << one.fits[0].standard_error;
  EXPECT_TRUE(order_matches(one.fits[1], 2, tol)) << one.fits[1].order << " +- " << one.fits[1].standard_error;
  // The error map is the signed error at map_step: its largest magnitude is that row's max error.
  float m = 0;
  for (float v : one.error_maps[1].pixels) m = std::max(m, std::abs(v));
  EXPECT_FLOAT_EQ(m, static_cast<float>(one.rows[4].max_error));
}

}  // namespace
}  // namespace vrv

namespace vrv {
namespace {

std::string shipped_study() {
  return read_study_text(std::filesystem::path(VRV_SOURCE_DIR) / "studies" / "segment-rules" / "segment-rules.toml");
}

// A bad study file is one line naming the file, the key and the reason ("accepted" for a good one).
std::string error_of(const std::string& text) {
  const toml::table doc = parse_study_toml(text, "bad.toml");
  const StudyReader reader("bad.toml");
  try {
    find_study_kind("segment_rules")(StudyInput{doc, reader, "bad"});
  } catch (const StudyFileError& e) {
    return e.what();
  }
  return "accepted";
}

// The shipped file with its first `edit_from` replaced by `edit_to`.
std::string parse_error(const std::string& edit_from, const std::string& edit_to) {
  std::string text = shipped_study();
  const auto at = text.find(edit_from);
  if (at == std::string::npos) return "edit not found: " + edit_from;
  return error_of(text.replace(at, edit_from.size(), edit_to));
}

TEST(SegmentRules, BadFilesNameTheKey) {
  struct Case {
    const char *from, *to, *error;
  };
  const Case cases[] = {
      {"map_step = 0.04", "map_step = 0.03", "bad.toml: render[0].map_step: must be one of steps and of quick_steps"},
      {"alpha_top = 0.9990234375", "alpha_top = 1.0", "bad.toml: unit_segment.alpha_top: must be in (0, 1)"},
      {"rule = \"moreland\"", "rule = \"simpson\"",
       "bad.toml: images.rule[4].rule: unknown value 'simpson' (one of riemann, alpha, trapezoid, exact_linear, moreland)"},
      // It said "must be a step strategy (step, vtk, inviwo)", leaving out two it takes.
      {"strategy = \"inviwo\"", "strategy = \"entry\"",
       "bad.toml: images.strategy: 'entry' is not taken here (one of step, vtk, inviwo, partial, exit_anchored)"},
      {"quick_points = 21", "quick_point = 21",
       "bad.toml: unit_segment.quick_point: unknown key (allowed: points, quick_points, alpha_top, identity_tolerance, "
       "independent_tolerance, max_error)"},
      // A gated order needs three steps for its tolerance (two ran the whole study, then failed).
      {"quick_steps = [0.04, 0.02, 0.01]", "quick_steps = [0.04, 0.02]",
       "bad.toml: render[0].quick_steps: at least three steps (a gated order and its spread)"},
      {"quick_steps = [0.04, 0.02, 0.01]", "quick_steps = [0.04, 0.02]\ncheck_orders = false", "accepted"},
      {"quick_steps = [0.04, 0.02, 0.01]", "quick_steps = [0.04]\ncheck_orders = false",
       "bad.toml: render[0].quick_steps: at least two steps (an order)"},
      // Repeats that would put two of an order's points in one place, or overwrite a render's images.
      {"quick_steps = [0.04, 0.02, 0.01]", "quick_steps = [0.04, 0.02, 0.04]",
       "bad.toml: render[0].quick_steps[2]: 0.04 is listed twice"},
      {"name = \"sharp\"", "name = \"smooth\"", "bad.toml: render[1].name: 'smooth' is listed twice (render[0] has it)"},
      {"rule = \"moreland\"", "rule = \"riemann\"", "bad.toml: images.rule[4].rule: 'riemann' is listed twice"},
      // Tolerances no result could meet: the checks failed after the whole run (exit 1).
      {"identity_tolerance = ", "identity_tolerance = -1.0 #",
       "bad.toml: unit_segment.identity_tolerance: must be >= 0, got -1"},
  };
  for (const Case& c : cases) EXPECT_EQ(parse_error(c.from, c.to), c.error) << c.to;
  // No render at all: the [[render]] tables cut, `render = []` among the top-level keys.
  std::string no_render = shipped_study();
  no_render.erase(no_render.find("[[render]]"));
  no_render.insert(no_render.find("[unit_segment]"), "render = []\n");
  EXPECT_EQ(error_of(no_render), "bad.toml: render: needs at least one [[render]]");
}

}  // namespace
}  // namespace vrv
