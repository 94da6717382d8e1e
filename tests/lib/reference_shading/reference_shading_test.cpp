// The shaded reference (lib/shading_weight.h through lib/reference_integrator.h) on rays with an
// independent mpmath truth (make_shading_truth.py, same folder: its own gradients, shading factor,
// kink finding and quadrature).  On every ray, at tol 1e-12, 1e-11 and 1e-10:
//   honest:     |value - truth| <= error_estimate, both finite;
//   not absurd: error_estimate <= max(100 max(|error|, floor), tol) (the adversarial test's rule);
//   met:        the tolerance is met (no cap reached), at 1e-11 and 1e-10;
// except on Marschner-Lobb's axis (a line of vanishing gradient), where only honesty is asserted.
// And the cases the definitions pin down without a truth file: ambient alone is the unshaded
// integral scaled; a grid whose gradient vanishes shades with the ambient term alone; three equal
// RGB channels are the grey shaded ray bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/reference_channels.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"
#include "lib/scene_file.h"
#include "tests/lib/truth_lines.h"

namespace vrv::reference_shading_test {
namespace {

struct ShadedRay {
  std::string cls, tag, scene_toml, truth_text;
  Vec3 origin, direction;
  long double truth = 0;
  double floor = 0;
  std::vector<double> grid_nodes;
};

const std::vector<ShadedRay>& rays() {
  static const std::vector<ShadedRay> all = [] {
    std::vector<ShadedRay> out;
    for (const nlohmann::json& j : test::truth_lines("tests/lib/reference_shading/shading_rays.jsonl")) {
      ShadedRay r;
      r.cls = j["class"];
      r.tag = j["tag"];
      r.scene_toml = j["scene"];
      r.origin = test::hex_vec3(j["origin"]);
      r.direction = test::hex_vec3(j["direction"]);
      r.truth_text = j["truth"];
      r.truth = std::strtold(r.truth_text.c_str(), nullptr);
      r.floor = j["floor"];
      if (j.contains("grid_nodes"))
        for (const auto& v : j["grid_nodes"]) r.grid_nodes.push_back(test::hex_double(v));
      out.push_back(std::move(r));
    }
    return out;
  }();
  return all;
}

TEST(ShadedReference, DataCoverEveryClass) {
  std::vector<std::string> classes;
  for (const ShadedRay& r : rays()) classes.push_back(r.cls);
  for (const char* c : {"blinn", "phong", "headlight", "highlight", "grazing", "far", "grid", "flat", "thick",
                        "opacity", "miss"})
    EXPECT_NE(std::find(classes.begin(), classes.end(), c), classes.end()) << c;
}

TEST(ShadedReference, GridNodesAreTheTruthsNodes) {
  for (const ShadedRay& r : rays()) {
    if (!r.grid_nodes.empty()) test::expect_grid_nodes_are_the_truths(r.scene_toml, r.grid_nodes, r.tag);
  }
}

// met: whether the tolerance must be met (the shaded floor, the normal's rounding amplified by the
// specular term, is about 1e-12 on Marschner-Lobb at fM = 6: at 1e-12 honesty and "not absurd" are
// asserted, and the tolerance from 1e-11 on).
void check_against_truth(double tol, bool met) {
  int checked = 0;
  for (const ShadedRay& r : rays()) {
    const Scene scene = parse_scene(r.scene_toml, r.tag);
    ASSERT_TRUE(scene.shading) << r.tag;
    const ReferenceResult res = integrate_reference(scene, make_ray(r.origin, r.direction), {tol});
    const long double error = static_cast<long double>(res.value) - r.truth;
    const double bound = std::max(100 * std::max(static_cast<double>(std::fabs(error)), r.floor), tol);
    const bool finite = std::isfinite(res.value) && std::isfinite(res.error_estimate);
    EXPECT_TRUE(finite && std::fabs(error) <= static_cast<long double>(res.error_estimate))
        << fmt::format("[{} | {}] tol {:.0e}: DISHONEST value {:.17g} truth {} error {:.3Le} estimate {:.3e}", r.cls,
                       r.tag, tol, res.value, r.truth_text, error, res.error_estimate);
    ++checked;
    // A ray along Marschner-Lobb's axis runs through a line where the gradient vanishes (its
    // radial part) and meets isolated zeros of the rest: the estimate there is honest but loose
    // (1e-7 to 1e-3 today, docs/shading.md "Not done yet"), and the ray says it missed.
    if (r.tag.rfind("axis_", 0) == 0) {
      EXPECT_EQ(res.tolerance_met, res.error_estimate <= tol) << r.tag;
      continue;
    }
    EXPECT_LE(res.error_estimate, bound) << fmt::format(
        "[{} | {}] tol {:.0e}: ABSURD estimate {:.3e}, error {:.3Le}, floor {:.3g}", r.cls, r.tag, tol,
        res.error_estimate, error, r.floor);
    if (!met) continue;
    EXPECT_TRUE(res.tolerance_met) << fmt::format("[{} | {}] tol {:.0e}: missed, estimate {:.3e}, {} evaluations",
                                                  r.cls, r.tag, tol, res.error_estimate, res.evaluations);
  }
  EXPECT_EQ(checked, static_cast<int>(rays().size()));
}

TEST(ShadedReference, HonestAndNotAbsurdAtTol1em12) { check_against_truth(1e-12, false); }
TEST(ShadedReference, HonestAndNotAbsurdAndMetAtTol1em11) { check_against_truth(1e-11, true); }
TEST(ShadedReference, HonestAndNotAbsurdAndMetAtTol1em10) { check_against_truth(1e-10, true); }

Scene default_with(const Shading& shading) {
  Scene scene = default_scene();
  scene.shading = shading;
  return scene;
}

// S = ambient everywhere: the integral is the unshaded one with emission scaled by ambient (the
// background is not shaded), each within its own estimate.
TEST(ShadedReference, AmbientAloneScalesTheEmission) {
  Shading flat;
  flat.ambient = 0.37, flat.diffuse = 0, flat.specular = 0;
  const Scene shaded = default_with(flat);
  const Scene plain = default_scene();
  for (const Vec3& d : {Vec3(0.1, 0.2, 1), Vec3(1, -0.3, 0.2), Vec3(-0.4, 1, 0.7)}) {
    const Ray ray = make_ray(-3 * d.normalized() + Vec3(0.05, -0.1, 0.02), d);
    const ReferenceResult a = integrate_reference(shaded, ray, {1e-12});
    const ReferenceResult b = integrate_reference(plain, ray, {1e-12});
    EXPECT_TRUE(a.tolerance_met && b.tolerance_met);
    EXPECT_NEAR(a.value, 0.37 * b.value, a.error_estimate + 0.37 * b.error_estimate) << d.transpose();
    EXPECT_GT(b.value, 0.01);
  }
}

// A grid whose nodes are all equal has no gradient: S = ambient, whatever the light.
TEST(ShadedReference, AVanishingGradientShadesWithTheAmbientTermAlone) {
  Scene scene = default_scene();
  scene.field = GridField(scene.box, {5, 4, 6}, GridLayout::node, Interpolation::trilinear,
                          std::vector<double>(5 * 4 * 6, 0.6));
  Shading s;
  s.light = Vec3(0.2, 0.3, 0.9);
  s.two_sided = false;
  scene.shading = s;
  Scene plain = scene;
  plain.shading.reset();
  const Ray ray = make_ray(Vec3(-3, 0.1, 0.2), Vec3(1, 0.05, 0.02));
  const ReferenceResult a = integrate_reference(scene, ray, {1e-12});
  const ReferenceResult b = integrate_reference(plain, ray, {1e-12});
  EXPECT_TRUE(a.tolerance_met);
  EXPECT_NEAR(a.value, s.ambient * b.value, a.error_estimate + s.ambient * b.error_estimate);
  EXPECT_GT(b.value, 0.1);
}

// The same transfer function in three channels: every channel is the grey shaded ray, bit for bit.
TEST(ShadedReference, EqualChannelsAreTheGreyShadedRayBitwise) {
  Shading s;
  s.light = Vec3(0.3, -0.5, 0.8);
  Scene grey = default_with(s);
  Scene rgb = grey;
  rgb.color = ColorChannels{{grey.transfer, grey.transfer, grey.transfer}, {0.0, 0.0, 0.0}};
  for (const Vec3& d : {Vec3(0.1, 0.2, 1), Vec3(1, -0.3, 0.2)}) {
    const Ray ray = make_ray(-3 * d.normalized(), d);
    const ReferenceResult one = integrate_reference(grey, ray, {1e-11});
    const ChannelsReferenceResult three = integrate_color_reference(rgb, ray, {1e-11});
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(three.channel[c].value, one.value) << c;
      EXPECT_EQ(three.channel[c].error_estimate, one.error_estimate) << c;
    }
  }
}

// Channels of different emission, breakpoints and jumps under one extinction, on a grid: the RGB
// walk computes S once for the three and cuts every channel at all their crossings, so a channel
// is not its own grey shaded ray bit for bit, but the same integral: within both estimates, each
// meeting the tolerance (a channel given another's S or cuts wrongly would be far outside).
TEST(ShadedReference, DistinctChannelsAreEachChannelsGreyShadedRay) {
  Shading s;
  s.light = Vec3(0.3, -0.5, 0.8);
  s.specular = 0.3, s.shininess = 12;
  Scene grey = default_with(s);
  grey.field = make_grid(grey.box, MarschnerLobb{}, {17, 17, 17}, GridLayout::node, Interpolation::trilinear);
  const PiecewiseLinear extinction({{0, 0.2}, {0.5, 1.5}, {1, 0.6}});
  const auto channel = [&](std::vector<ControlPoint> emission) {
    return TransferFunction::emission_extinction(PiecewiseLinear(std::move(emission)), extinction);
  };
  Scene rgb = grey;
  rgb.color = ColorChannels{{channel({{0, 0}, {1, 1}}), channel({{0, 0.8}, {0.3, 0.1}, {1, 0.4}}),
                             channel({{0, 0.1}, {0.6, 0.1}, {0.6, 0.9}, {1, 0.2}})},
                            {0.0, 0.0, 0.0}};
  for (const Vec3& d : {Vec3(0.1, 0.2, 1), Vec3(1, -0.3, 0.2), Vec3(-0.4, 1, 0.7)}) {
    const Ray ray = make_ray(-3 * d.normalized() + Vec3(0.05, -0.1, 0.02), d);
    const ChannelsReferenceResult three = integrate_color_reference(rgb, ray, {1e-11});
    for (int c = 0; c < 3; ++c) {
      grey.transfer = rgb.color->transfer[c];
      const ReferenceResult one = integrate_reference(grey, ray, {1e-11});
      EXPECT_TRUE(three.channel[c].tolerance_met && one.tolerance_met) << c << " " << d.transpose();
      EXPECT_LE(std::abs(three.channel[c].value - one.value), three.channel[c].error_estimate + one.error_estimate)
          << c << " " << d.transpose();
    }
  }
}

// Where the normal turns fast (n.v and n.l pass through 0 within 2e-4 of each other) or a narrow
// highlight rides on a cell, S puts a small, slowly decaying part on a piece's coefficients; a short
// rule's last two could be small by chance.  These rays' estimates at tol 1e-9 were 15x (the
// analytic field) and 1.07x (its 17^3 grid) below their errors; each is now within its estimate of
// the same ray at tol 1e-14.
TEST(ShadedReference, ATurningNormalOrANarrowHighlightIsCharged) {
  Shading s;
  s.light = Vec3(0.3, -0.5, 0.8);
  s.specular = 0.3, s.shininess = 12;
  Scene analytic = default_with(s);
  analytic.transfer = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {1, 2}}), PiecewiseLinear({{0.2, 0}, {0.45, 300}, {0.45, 30}, {0.8, 600}}));
  Scene grid = default_with(s);
  grid.field = make_grid(grid.box, MarschnerLobb{}, {17, 17, 17}, GridLayout::node, Interpolation::trilinear);
  grid.transfer = TransferFunction::emission_extinction(PiecewiseLinear({{0, 0}, {1, 2}}),
                                                        PiecewiseLinear({{0, 0.3}, {0.45, 2.5}, {0.45, 0.8}, {1, 1.6}}));
  grid.background = 0;
  const Ray grid_ray = make_ray(Vec3(-0.023636461594730734, -1.5968094411505112, -2.7189964313381663),
                                Vec3(0.081879274480551517, 0.51065861195368401, 0.85587590598642005));
  const Ray analytic_ray = make_ray(Vec3(1.7321290038616448, -0.45580335551669998, -2.0380299497020422),
                                    Vec3(-0.63636602635486217, 0.13193348147528305, 0.76002094508449825));
  for (const auto& [scene, ray] : {std::pair{&analytic, analytic_ray}, std::pair{&grid, grid_ray}}) {
    const ReferenceResult tight = integrate_reference(*scene, ray, {1e-14});
    for (double tol : {1e-9, 1e-6}) {
      const ReferenceResult r = integrate_reference(*scene, ray, {tol});
      EXPECT_TRUE(r.tolerance_met) << tol;
      EXPECT_LE(std::abs(r.value - tight.value), r.error_estimate + tight.error_estimate)
          << "tol " << tol << " estimate " << r.error_estimate;
    }
  }
}

// Shading changes the value (the tests above would pass if it were ignored by a scaled route).
TEST(ShadedReference, ALightChangesTheValue) {
  Shading left, right;
  left.light = Vec3(-1, 0, 0.2), right.light = Vec3(1, 0, 0.2);
  const Ray ray = make_ray(Vec3(0.1, -3, 0.05), Vec3(0, 1, 0));
  const double a = integrate_reference(default_with(left), ray, {1e-12}).value;
  const double b = integrate_reference(default_with(right), ray, {1e-12}).value;
  EXPECT_GT(std::abs(a - b), 1e-3 * std::max(std::abs(a), std::abs(b)));
}

}  // namespace
}  // namespace vrv::reference_shading_test
