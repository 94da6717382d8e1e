// The visibility study's own computations: the opacity identities in stable form, the radiance
// bound, block extinction ranges, the POF chord and the culling renderer.
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lib/discrete_raycast.h"
#include "lib/util/parallel.h"
#include "lib/scene.h"
#include "lib/study_file.h"
#include "studies/engine/study_driver.h"
#include "studies/visibility/identities.h"
#include "studies/visibility/culling.h"

namespace vrv {
namespace visibility_test {  // named: the unity build joins test files, and helper names recur

TEST(VisibilityIdentity, ScaledOpacityIsOneMinusTransparencyToTheK) {
  for (double a : {0.01, 0.05, 0.3, 0.9, 0.999})
    for (double k : {0.25, 1.0, 2.0, 3.5, 10.0})
      EXPECT_NEAR(scaled_opacity(a, k), 1 - std::pow(1 - a, k), 1e-15) << a << " " << k;
}

TEST(VisibilityIdentity, ScaledOpacityKeepsTinyOpacities) {
  // 1 - (1 - 1e-20)^3 is 0 in the naive form; the stable form keeps 3e-20.
  EXPECT_EQ(1 - std::pow(1 - 1e-20, 3.0), 0.0);
  EXPECT_NEAR(scaled_opacity(1e-20, 3) / 3e-20, 1, 1e-15);
}

TEST(VisibilityIdentity, CombinedOpacityIsTheProductOfTransparencies) {
  const double a[] = {0.2, 0.05, 0.6}, k[] = {2.0, 0.5, 1.0};
  const double expected = 1 - std::pow(0.8, 2.0) * std::pow(0.95, 0.5) * 0.4;
  EXPECT_NEAR(combined_opacity(a, k), expected, 1e-15);
  // One basis: the scaled opacity; k = 2 is the basis combined with itself.
  const double one[] = {0.3}, kk[] = {2.0}, twice[] = {0.3, 0.3}, ones[] = {1.0, 1.0};
  EXPECT_NEAR(combined_opacity(one, kk), scaled_opacity(0.3, 2), 1e-16);
  EXPECT_NEAR(combined_opacity(twice, ones), scaled_opacity(0.3, 2), 1e-16);
}

TEST(VisibilityIdentity, DepthsKeepTheTransparencyWhereAlphaIsNearOne) {
  const double phi[] = {30.0, 5.0}, k[] = {0.25, 1.0};
  const double exact = -std::expm1(-(0.25 * 30.0 + 5.0));
  EXPECT_NEAR(combined_opacity_of_depths(phi, k), exact, 1e-16);
  // Through alpha, 1 - alpha = e^-30 has lost its digits: the same formula misses by far more.
  const double a[] = {-std::expm1(-30.0), -std::expm1(-5.0)};
  EXPECT_GT(std::abs(combined_opacity(a, k) - exact), 1e-12);
}

TEST(VisibilityIdentity, SamplesToThresholdIsTheRealSolution) {
  const double l = samples_to_threshold(0.05, 0.95);
  EXPECT_NEAR(l, std::log(0.05) / std::log(0.95), 1e-12);
  // The opacity reaches the threshold exactly at l samples.
  EXPECT_NEAR(scaled_opacity(0.05, l), 0.95, 1e-14);
  EXPECT_LT(scaled_opacity(0.05, std::floor(l)), 0.95);
  EXPECT_GE(scaled_opacity(0.05, std::ceil(l)), 0.95);
}

PiecewiseLinear curve(std::vector<ControlPoint> p) { return PiecewiseLinear(std::move(p)); }

TEST(VisibilityBound, MaxColourOfProportionalTransferFunctionIsKappa) {
  const auto tau = curve({{0, 1}, {0.5, 4}, {1, 2}});
  const auto tf = TransferFunction::emission_extinction(curve({{0, 0.3}, {0.5, 1.2}, {1, 0.6}}), tau);
  EXPECT_NEAR(max_colour(tf), 0.3, 1e-15);
  EXPECT_NEAR(max_radiance(tf, 0.7), 0.7, 0);
}

TEST(VisibilityBound, MaxColourBoundsDenselySampledColour) {
  const auto tf = TransferFunction::emission_extinction(curve({{0.0, 0.4}, {0.5, 3.0}, {1.0, 1.2}}),
                                                        curve({{0.0, 4.0}, {0.5, 6.0}, {1.0, 8.0}}));
  const double m = max_colour(tf);
  double seen = 0;
  for (int i = -100; i <= 1100; ++i) {
    const double v = i / 1000.0;
    seen = std::max(seen, tf.emission(v) / tf.extinction(v));
  }
  EXPECT_GE(m, seen);
  EXPECT_NEAR(m, seen, 1e-12);
}

TEST(VisibilityBound, MaxColourIsInfiniteWhereEmissionHasNoExtinction) {
  const auto tf = TransferFunction::emission_extinction(curve({{0, 1}}), curve({{0, 0}, {1, 1}}));
  EXPECT_TRUE(std::isinf(max_colour(tf)));
}

TEST(VisibilityCurves, SumAgreesPointwiseIncludingJumps) {
  const auto a = curve({{0, 1}, {0.3, 2}, {0.3, 5}, {1, 0}});
  const auto b = curve({{0.2, 0}, {0.6, 3}});
  const auto s = sum(a, b);
  for (int i = -10; i <= 110; ++i) {
    const double v = i / 100.0;
    EXPECT_NEAR(s(v), a(v) + b(v), 1e-14) << v;
  }
  // Just left of the jump at 0.3.
  const double v = std::nextafter(0.3, 0.0);
  EXPECT_NEAR(s(v), a(v) + b(v), 1e-12);
}

TEST(VisibilityBlocks, ExtinctionRangeMatchesDenseSampling) {
  const auto tf = TransferFunction::emission_extinction(curve({{0, 0}}), curve({{0, 4}, {0.3, 1}, {0.3, 7}, {1, 2}}));
  for (auto [lo, hi] : {std::pair{0.0, 0.2}, std::pair{0.1, 0.5}, std::pair{0.35, 0.9}, std::pair{-1.0, 2.0}}) {
    double mn = 1e300, mx = 0;
    std::vector<double> vs;
    for (int i = 0; i <= 10000; ++i) vs.push_back(lo + (hi - lo) * i / 10000.0);
    for (double b : tf.breakpoints())  // the extremes of a piecewise-linear curve sit there
      if (b >= lo && b <= hi) vs.push_back(b);
    for (double v : vs) {
      const double t = tf.extinction(v);
      mn = std::min(mn, t), mx = std::max(mx, t);
    }
    EXPECT_LE(extinction_min(tf, lo, hi), mn);
    EXPECT_GE(extinction_max(tf, lo, hi), mx);
    EXPECT_NEAR(extinction_min(tf, lo, hi), mn, 1e-3);
    EXPECT_NEAR(extinction_max(tf, lo, hi), mx, 1e-3);
  }
}

GridField small_grid() {
  return make_grid(Box{}, MarschnerLobb{}, {17, 17, 17}, GridLayout::node, Interpolation::trilinear);
}

TEST(VisibilityBlocks, BlockExtinctionBoundsEverySampleInTheBlock) {
  const GridField g = small_grid();
  const auto tf = TransferFunction::emission_extinction(curve({{0, 0}}), curve({{0, 1}, {0.5, 6}, {1, 3}}));
  const BlockGrid blocks{Box{}, {4, 4, 4}};
  const BlockExtinction ext = block_extinction(g, tf, blocks);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const int b = blocks.index_of(p);
    const double tau = tf.extinction(g.value(p));
    ASSERT_GE(tau, ext.tau_min[b]);
    ASSERT_LE(tau, ext.tau_max[b]);
  }
}

TEST(VisibilityBlocks, IndexOfFindsTheBlockHoldingThePoint) {
  const BlockGrid blocks{Box{}, {8, 4, 2}};
  for (int b = 0; b < blocks.count(); ++b) {
    const Box bb = blocks.block(b);
    EXPECT_EQ(blocks.index_of(0.5 * (bb.min + bb.max)), b);
  }
}

TEST(VisibilityViews, DirectionsAreUnitAndAvoidThePoles) {
  for (int j = 0; j < 36; ++j)
    for (int i = 0; i < 36; ++i) {
      const Vec3 d = view_direction(i, j, 36, 36);
      EXPECT_NEAR(d.norm(), 1, 1e-15);
      EXPECT_LT(std::abs(d[2]), 1.0);
    }
  EXPECT_DOUBLE_EQ(view_phi_degrees(0, 36), 2.5);
  EXPECT_DOUBLE_EQ(view_theta_degrees(35, 36), 350);
}

TEST(VisibilityViews, CreditedChordWithFractionOneIsTheLongestChord) {
  const Box block{Vec3(0, 0, 0), Vec3(0.25, 0.25, 0.25)};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < 200; ++n) {
    const Vec3 d = Vec3(u(rng), u(rng), u(rng)).normalized();
    const double longest = credited_chord(block.extent(), d, 1.0);
    double seen = 0;
    for (int m = 0; m < 200; ++m) {
      const Vec3 through(0.25 * (u(rng) + 1) / 2, 0.25 * (u(rng) + 1) / 2, 0.25 * (u(rng) + 1) / 2);
      const auto iv = clip(Ray{through - 2 * d, d}, block);
      ASSERT_TRUE(iv);
      ASSERT_LE(iv->length(), longest * (1 + 1e-12));
      seen = std::max(seen, iv->length());
    }
    EXPECT_GT(seen, 0.5 * longest);
  }
}

Scene culling_scene() {
  Scene s;
  s.field = small_grid();
  s.transfer = TransferFunction::emission_extinction(curve({{0, 0.8}, {0.5, 3}, {1, 2}}),
                                                     curve({{0, 8}, {0.5, 12}, {1, 10}}));
  s.background = 0.2;
  return s;
}

TEST(VisibilityCulling, UnculledImageIsTheAlphaRuleRaycast) {
  const Scene s = culling_scene();
  const GridField& g = std::get<GridField>(s.field);
  const BlockGrid blocks{s.box, {4, 4, 4}};
  const BlockExtinction ext = block_extinction(g, s.transfer, blocks);
  CullingOptions o;
  o.side = 32;  // enough pixels on two threads to expose shared per-ray state
  o.step = 0.05;
  const Vec3 d = view_direction(2, 3, 6, 6);
  const ViewCulling v = cull_view(s, g, blocks, ext, std::vector<double>(blocks.count(), 0.0), d, o);
  EXPECT_EQ(v.culled[kPof], 0);  // a POF of zero opacity never hides anything
  DiscreteConfig cfg;
  cfg.rule = SegmentRule::alpha;
  cfg.sampling.strategy = Strategy::step;
  cfg.sampling.step = o.step;
  const Camera cam = view_camera(s.box, d, o.side);
  long samples = 0;
  for (int y = 0; y < o.side; ++y)
    for (int x = 0; x < o.side; ++x) {
      const DiscreteResult r = discrete_raycast(s, cam.ray(x, y), cfg);
      samples += r.samples;
      EXPECT_NEAR(v.image_all.at(x, y), r.value, 1e-6 * std::max(1.0, std::abs(r.value)));
      EXPECT_EQ(v.image[kPof].at(x, y), v.image_all.at(x, y));
    }
  EXPECT_EQ(v.samples_all, samples);
  EXPECT_EQ(v.samples[kPof], samples);
}

TEST(VisibilityCulling, CullsConservativelyWithinTheBound) {
  const Scene s = culling_scene();
  const GridField& g = std::get<GridField>(s.field);
  const BlockGrid blocks{s.box, {8, 8, 8}};
  const BlockExtinction ext = block_extinction(g, s.transfer, blocks);
  CullingOptions o;
  o.side = 24;
  o.step = 0.025;
  o.chord_fraction = 0.75;
  const double bound = (1 - o.threshold) * max_radiance(s.transfer, s.background);
  int culled = 0;
  for (int i = 0; i < 4; ++i) {
    const Vec3 d = view_direction(i, 1 + i, 4, 6);
    std::vector<double> pof(blocks.count());
    for (int b = 0; b < blocks.count(); ++b)
      pof[b] = pof_depth(ext.tau_min[b], credited_chord(blocks.size(), d, o.chord_fraction), o.step);
    const ViewCulling v = cull_view(s, g, blocks, ext, pof, d, o);
    culled += v.culled[kPof];
    for (int m = 0; m < kCullMethods; ++m) {
      EXPECT_GE(v.min_front_opacity[m], o.threshold) << kCullMethodNames[m];
      EXPECT_LE(v.max_error[m], bound) << kCullMethodNames[m];
      EXPECT_LE(v.samples[m], v.samples_all);
    }
    // The chord bound credits every pixel at least what the POF credits it: it culls as much.
    EXPECT_GE(v.culled[kChord], v.culled[kPof]);
  }
  EXPECT_GT(culled, 0);  // the test is not vacuous
}

TEST(VisibilityCulling, SameImagesForOneAndTwoThreads) {
  const Scene s = culling_scene();
  const GridField& g = std::get<GridField>(s.field);
  const BlockGrid blocks{s.box, {4, 4, 4}};
  const BlockExtinction ext = block_extinction(g, s.transfer, blocks);
  CullingOptions o;
  o.side = 16;
  const Vec3 d = view_direction(1, 2, 6, 6);
  std::vector<double> pof(blocks.count());
  for (int b = 0; b < blocks.count(); ++b)
    pof[b] = pof_depth(ext.tau_min[b], credited_chord(blocks.size(), d, 0.75), o.step);
  ViewCulling one, two;
  {
    const ThreadLimit limit(1);
    one = cull_view(s, g, blocks, ext, pof, d, o);
  }
  {
    const ThreadLimit limit(2);
    two = cull_view(s, g, blocks, ext, pof, d, o);
  }
  for (int m = 0; m < kCullMethods; ++m) {
    EXPECT_EQ(one.image[m].pixels, two.image[m].pixels);
    EXPECT_EQ(one.culled[m], two.culled[m]);
  }
}

std::string study_text() {
  std::ifstream f(std::string(VRV_SOURCE_DIR) + "/studies/visibility/visibility.toml");
  std::stringstream text;
  text << f.rdbuf();
  return text.str();
}

// The message parse_visibility throws for `text` ("" when it parses).
std::string parse_error(const std::string& text) {
  const StudyReader reader("bad.toml");
  try {
    const toml::table doc = parse_study_toml(text, "bad.toml");
    const StudyParse parse = find_study_kind("visibility");
    if (!parse) return "no kind";
    parse(StudyInput{doc, reader, "bad"});
  } catch (const StudyFileError& e) {
    return e.what();
  }
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(VisibilityStudyFile, TheStudyParsesAndBadKeysGiveOneLine) {
  const std::string text = study_text();
  EXPECT_EQ(parse_error(text), "");
  const std::pair<std::string, std::string> cases[] = {
      {replaced(text, "chord_fraction = 0.75", "chord_fraction = -1"), "bad.toml: culling.chord_fraction:"},
      {replaced(text, "threshold = 0.95\nstep", "threshold = 1.5\nstep"), "bad.toml: culling.threshold:"},
      {replaced(text, "pof_block = [4, 4, 4]", "pof_block = [4, 9, 4]"), "bad.toml: culling.pof_block:"},
      {replaced(text, "ray_samples = 200", "ray_samples = 50"), "bad.toml: threshold_samples.ray_samples:"},
      {replaced(text, "kind = \"grid\"", "kind = \"marschner_lobb\"\nfoo = 1"), "bad.toml: scene"},
      {replaced(text, "[identity]", "[identity]\nspeed = 3"), "bad.toml: identity.speed:"},
  };
  for (const auto& [bad, start] : cases) {
    const std::string e = parse_error(bad);
    EXPECT_EQ(e.rfind(start, 0), 0u) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

}  // namespace visibility_test
}  // namespace vrv
