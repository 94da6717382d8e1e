// The discrete raycaster on shaded scenes (lib/shading.h, lib/gradient_scheme.h): each sample's
// emission times S from the gradient taken by the chosen scheme, against the shaded reference.
#include <gtest/gtest.h>

#include <cmath>

#include "lib/discrete_raycast.h"
#include "lib/gradient_scheme.h"
#include "lib/option_error.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"
#include "lib/scene_file.h"

namespace vrv::discrete_shading_test {
namespace {

Scene lit_scene() {
  Scene scene = default_scene();
  Shading s;
  s.light = Vec3(0.3, -0.4, 0.87);
  scene.shading = s;
  return scene;
}

DiscreteConfig trapezoid(double step, GradientScheme scheme) {
  DiscreteConfig c;
  c.rule = SegmentRule::trapezoid;
  c.sampling.strategy = Strategy::step;
  c.sampling.step = step;
  c.gradient = scheme;
  return c;
}

const Ray kRay = make_ray(Vec3(0.13, -0.21, -3), Vec3(0.05, 0.1, 1));

// S = ambient everywhere: every sample's emission scaled, the transmittance untouched.
TEST(DiscreteShading, AmbientAloneScalesTheEmission) {
  Scene shaded = default_scene();
  Shading flat;
  flat.ambient = 0.4, flat.diffuse = 0, flat.specular = 0;
  shaded.shading = flat;
  for (SegmentRule rule : {SegmentRule::riemann, SegmentRule::alpha, SegmentRule::trapezoid}) {
    DiscreteConfig c = trapezoid(0.01, GradientScheme::analytic);
    c.rule = rule;
    const double a = discrete_raycast(shaded, kRay, c).value;
    const double b = discrete_raycast(default_scene(), kRay, c).value;
    EXPECT_NEAR(a, 0.4 * b, 1e-14) << segment_rule_name(rule);
    EXPECT_GT(b, 0.05);
  }
}

// With the exact gradient the shaded trapezoid rule converges to the shaded reference at order 2.
TEST(DiscreteShading, AnalyticGradientConvergesToTheShadedReference) {
  const Scene scene = lit_scene();
  const ReferenceResult ref = integrate_reference(scene, kRay, {1e-13});
  ASSERT_TRUE(ref.tolerance_met);
  double previous = 0;
  for (double step : {0.02, 0.01, 0.005}) {
    const double error = std::abs(discrete_raycast(scene, kRay, trapezoid(step, GradientScheme::analytic)).value - ref.value);
    if (previous > 0) {
      EXPECT_GT(previous / error, 3.0) << step;  // order 2: 4x per halving
      EXPECT_LT(previous / error, 5.5) << step;
    }
    previous = error;
  }
}

// Central differences at the sample approach the exact gradient as their offset shrinks.
TEST(DiscreteShading, CentralDifferencesApproachTheAnalyticGradient) {
  const Scene scene = lit_scene();
  const double exact = discrete_raycast(scene, kRay, trapezoid(0.01, GradientScheme::analytic)).value;
  double previous = 0;
  for (double h : {1e-2, 5e-3, 2.5e-3}) {
    DiscreteConfig c = trapezoid(0.01, GradientScheme::central);
    c.gradient_offset = h;
    const double d = std::abs(discrete_raycast(scene, kRay, c).value - exact);
    if (previous > 0) {
      EXPECT_GT(previous / d, 3.0) << h;  // O(h^2) differences
    }
    previous = d;
  }
  EXPECT_LT(previous, 1e-4);
}

// On a grid, node differences interpolated to the sample (Lee & Newman) are not the interpolant's
// gradient: their error against the shaded reference stays as the step shrinks, the exact
// gradient's does not.
TEST(DiscreteShading, NodeDifferencesLeaveAnErrorThatStepsDoNotRemove) {
  Scene scene = lit_scene();
  scene.field = make_grid(scene.box, MarschnerLobb{}, {17, 17, 17}, GridLayout::node, Interpolation::trilinear);
  const ReferenceResult ref = integrate_reference(scene, kRay, {1e-12});
  ASSERT_TRUE(ref.tolerance_met);
  const double analytic = std::abs(discrete_raycast(scene, kRay, trapezoid(0.002, GradientScheme::analytic)).value - ref.value);
  const double nodes = std::abs(discrete_raycast(scene, kRay, trapezoid(0.002, GradientScheme::nodes)).value - ref.value);
  const double nodes_finer = std::abs(discrete_raycast(scene, kRay, trapezoid(0.001, GradientScheme::nodes)).value - ref.value);
  EXPECT_GT(nodes, 10 * analytic);
  EXPECT_GT(nodes_finer, 0.5 * nodes);  // a plateau, not convergence
}

TEST(DiscreteShading, SchemesAreCheckedWhereTheyCannotApply) {
  const Scene scene = lit_scene();
  try {
    discrete_raycast(scene, kRay, trapezoid(0.01, GradientScheme::nodes));
    FAIL();
  } catch (const OptionError& e) {
    EXPECT_EQ(e.option(), Option::gradient);
  }
  DiscreteConfig c = trapezoid(0.01, GradientScheme::analytic);
  c.gradient_offset = 0.01;
  EXPECT_THROW(discrete_raycast(scene, kRay, c), OptionError);
  c.gradient = GradientScheme::central;
  c.gradient_offset = -1;
  EXPECT_THROW(discrete_raycast(scene, kRay, c), OptionError);
}

// Shading at the nodes (pre-classification, pre-shading): the classes interpolated from each
// node's classified colour times S of its node gradient.
DiscreteConfig shaded_at_nodes(double step) {
  DiscreteConfig c = trapezoid(step, GradientScheme::nodes);
  c.classification = Classification::pre;
  c.shade_at = ShadeAt::nodes;
  return c;
}

Scene opacity_color_scene(Scene scene) {
  scene.transfer = TransferFunction::opacity_color(PiecewiseLinear({{0, 0}, {1, 0.6}}),
                                                   PiecewiseLinear({{0, 0.2}, {1, 1}}), 0.25);
  return scene;
}

// S = ambient at every node: the shaded nodes are the unshaded classes times it, in both
// transfer-function conventions and with premultiplied colour.
TEST(DiscreteShading, ShadingAtNodesWithAmbientAloneScalesThePreClassifiedRaycast) {
  Scene shaded = default_scene();
  shaded.field = make_grid(shaded.box, MarschnerLobb{}, {17, 17, 17}, GridLayout::node, Interpolation::trilinear);
  Shading flat;
  flat.ambient = 0.4, flat.diffuse = 0, flat.specular = 0;
  shaded.shading = flat;
  for (const Scene& scene : {shaded, opacity_color_scene(shaded)})
    for (ColorConvention color : {ColorConvention::straight, ColorConvention::premultiplied}) {
      DiscreteConfig at_nodes = shaded_at_nodes(0.01);
      at_nodes.rule = SegmentRule::alpha;
      at_nodes.color = color;
      DiscreteConfig plain = at_nodes;
      plain.shade_at = ShadeAt::samples;
      Scene unshaded = scene;
      unshaded.shading.reset();
      const double a = discrete_raycast(scene, kRay, at_nodes).value;
      const double b = discrete_raycast(unshaded, kRay, plain).value;
      EXPECT_NEAR(a, 0.4 * b, 1e-14) << color_convention_name(color);
      EXPECT_GT(b, 0.01);
    }
}

// A linear field: every node difference is its exact gradient, S is one number at every node and
// every sample, and shading at the nodes is shading at the samples (to rounding).
TEST(DiscreteShading, ShadingAtNodesIsShadingAtSamplesWhereTheNormalIsConstant) {
  Scene scene = lit_scene();
  scene.field = make_grid(scene.box, LinearRamp{Vec3(0.2, 0.1, 0.15), 0.5}, {9, 9, 9}, GridLayout::node,
                          Interpolation::trilinear);
  DiscreteConfig at_samples = shaded_at_nodes(0.01);
  at_samples.shade_at = ShadeAt::samples;
  const double a = discrete_raycast(scene, kRay, shaded_at_nodes(0.01)).value;
  const double b = discrete_raycast(scene, kRay, at_samples).value;
  EXPECT_NEAR(a, b, 1e-13 * b);
  Scene unshaded = scene;
  unshaded.shading.reset();
  EXPECT_GT(std::abs(a - discrete_raycast(unshaded, kRay, at_samples).value), 1e-3);  // it does shade
}

// On Marschner-Lobb's grid the normals turn between nodes: interpolating shaded colours is not
// shading the interpolated normal.
TEST(DiscreteShading, ShadingAtNodesDiffersFromShadingAtSamplesWhereNormalsTurn) {
  Scene scene = lit_scene();
  scene.field = make_grid(scene.box, MarschnerLobb{}, {17, 17, 17}, GridLayout::node, Interpolation::trilinear);
  DiscreteConfig at_samples = shaded_at_nodes(0.01);
  at_samples.shade_at = ShadeAt::samples;
  const double a = discrete_raycast(scene, kRay, shaded_at_nodes(0.01)).value;
  const double b = discrete_raycast(scene, kRay, at_samples).value;
  EXPECT_GT(std::abs(a - b), 1e-4 * std::abs(b));
}

TEST(DiscreteShading, ShadingAtNodesNeedsItsPipeline) {
  Scene scene = lit_scene();
  const auto refused = [&](const DiscreteConfig& c, const std::string& words) {
    try {
      discrete_raycast(scene, kRay, c);
      ADD_FAILURE() << "accepted: " << words;
    } catch (const OptionError& e) {
      EXPECT_EQ(e.option(), Option::shade_at);
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  DiscreteConfig analytic_field = shaded_at_nodes(0.01);  // pre-classification is refused first there
  analytic_field.gradient = GradientScheme::central;
  analytic_field.classification = Classification::post;
  refused(analytic_field, "needs a grid field");
  scene.field = make_grid(scene.box, MarschnerLobb{}, {9, 9, 9}, GridLayout::node, Interpolation::trilinear);
  DiscreteConfig post = shaded_at_nodes(0.01);
  post.classification = Classification::post;
  refused(post, "--classification pre and --gradient nodes");
  DiscreteConfig central = shaded_at_nodes(0.01);
  central.gradient = GradientScheme::central;
  refused(central, "--classification pre and --gradient nodes");
}

}  // namespace
}  // namespace vrv::discrete_shading_test
