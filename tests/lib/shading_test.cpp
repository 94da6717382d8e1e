// The shading factor (lib/shading.h), the fields' gradients it takes, the [shading] table of scene
// files, and the refusal of a shaded scene by what does not shade yet.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "analytic/linear_ramp.h"
#include "analytic/marschner_lobb.h"
#include "lib/grid_field.h"
#include "lib/scene.h"
#include "lib/scene_file.h"
#include "lib/scene_hash.h"
#include "lib/shading.h"
#include "tests/lib/scene_text.h"

namespace vrv::shading_test {
namespace {

Shading lit(Vec3 light, ShadingModel model = ShadingModel::blinn_phong) {
  Shading s;
  s.model = model;
  s.light = light;
  return s;
}

TEST(ShadingFactor, AVanishingGradientGivesTheAmbientTermAlone) {
  const ShadingFactor f(lit(Vec3(0, 0, 1)), Vec3(0, 0, -1));
  EXPECT_EQ(f(Vec3::Zero()), 0.2);
  // Too small to square, still a direction: not zero.
  EXPECT_GT(f(Vec3(0, 0, -1e-200)), 0.2);
}

TEST(ShadingFactor, HeadlightFacingTheEyeIsFullyLit) {
  Shading s;  // headlight, negative gradient, two-sided, Blinn-Phong
  const ShadingFactor f(s, Vec3(0, 0, 1));  // looking along +z: v = -z
  // grad f along +z: n = -grad = -z faces the eye: n.l = n.h = 1.
  EXPECT_DOUBLE_EQ(f(Vec3(0, 0, 3)), s.ambient + s.diffuse + s.specular);
  // Two-sided: the opposite gradient is turned to face the eye, the same light.
  EXPECT_DOUBLE_EQ(f(Vec3(0, 0, -3)), s.ambient + s.diffuse + s.specular);
  Shading one = s;
  one.two_sided = false;
  EXPECT_DOUBLE_EQ(ShadingFactor(one, Vec3(0, 0, 1))(Vec3(0, 0, -3)), s.ambient);
}

TEST(ShadingFactor, PhongAndBlinnPhongFollowTheirDefinitions) {
  const Vec3 dir = Vec3(0.2, -0.1, 1).normalized();
  const Vec3 light = Vec3(0.5, 0.4, -0.6);
  const Vec3 grad(-0.3, 0.7, -0.2);
  for (ShadingModel m : {ShadingModel::phong, ShadingModel::blinn_phong}) {
    Shading s = lit(light, m);
    s.normal = NormalSign::gradient, s.two_sided = false, s.shininess = 5;
    const Vec3 n = grad.normalized(), l = light.normalized(), v = -dir;
    const double spec = m == ShadingModel::phong ? (2 * n.dot(l) * n - l).dot(v) : n.dot((l + v).normalized());
    const double expected = s.ambient + s.diffuse * std::max(0.0, n.dot(l)) + s.specular * std::pow(std::max(0.0, spec), 5.0);
    EXPECT_NEAR(ShadingFactor(s, dir)(grad), expected, 1e-15) << shading_model_name(m);
  }
}

// The switch functions change sign exactly where a term starts or stops.
TEST(ShadingFactor, SwitchesAreWhereTheTermsTurnOn) {
  Shading s = lit(Vec3(1, 0, 0));
  s.two_sided = false, s.normal = NormalSign::gradient, s.specular = 0;  // the diffuse term's switch alone
  const ShadingFactor f(s, Vec3(0, 0, 1));
  EXPECT_GT(f.switch_value(1, Vec3(0.1, 0, 1)), 0);
  EXPECT_LT(f.switch_value(1, Vec3(-0.1, 0, 1)), 0);
  EXPECT_FALSE(f.has_switch(0));
  EXPECT_GT(f(Vec3(0.1, 0, -1)), s.ambient);
  EXPECT_EQ(f(Vec3(-0.1, 0, -1)), s.ambient);
}

TEST(ShadingValidation, NamesTheKey) {
  Shading s;
  s.diffuse = -1;
  try {
    validate(s);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("shading.diffuse: ", 0), 0u) << e.what();
  }
  s = Shading{};
  s.shininess = 0.5;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s = Shading{};
  s.light = Vec3::Zero();
  EXPECT_THROW(validate(s), std::invalid_argument);
}

// Each field's gradient against central differences of its own values.
template <class F>
void expect_gradient(const F& field, const Vec3& p, double tol) {
  const Vec3 g = field.piece_gradient(p, p);
  for (int a = 0; a < 3; ++a) {
    Vec3 e = Vec3::Zero();
    e[a] = 1e-6;
    const double numeric = (field.value(p + e) - field.value(p - e)) / 2e-6;
    EXPECT_NEAR(g[a], numeric, tol) << "axis " << a << " at " << p.transpose();
  }
}

TEST(FieldGradient, MarschnerLobbRampAndGridAgreeWithDifferences) {
  const MarschnerLobb ml;
  for (const Vec3& p : {Vec3(0.3, -0.2, 0.7), Vec3(1e-9, 2e-9, -0.4), Vec3(-0.8, 0.55, 0.1)}) expect_gradient(ml, p, 1e-6);
  const LinearRamp ramp{Vec3(0.3, -2, 5), 1};
  expect_gradient(ramp, Vec3(0.1, 0.2, 0.3), 1e-8);
  const GridField grid = make_grid(Box{}, MarschnerLobb{}, {9, 7, 5}, GridLayout::node, Interpolation::trilinear);
  expect_gradient(grid, Vec3(0.13, -0.21, 0.37), 1e-7);  // inside a cell: the interpolant is smooth there
  const GridField cells = make_grid(Box{}, MarschnerLobb{}, {9, 7, 5}, GridLayout::cell, Interpolation::trilinear);
  expect_gradient(cells, Vec3(-0.43, 0.11, -0.29), 1e-7);
  // Beyond the outermost centres the cell layout is clamped: no change along that axis.
  EXPECT_EQ(cells.piece_gradient(Vec3(0.99, 0.1, 0.1), Vec3(0.99, 0.1, 0.1)).x(), 0.0);
}

// On a cell face the gradient is the one of the cell that holds `inside`.
TEST(FieldGradient, AGridFaceTakesTheSideOfItsPiece) {
  const GridField grid = make_grid(Box{}, MarschnerLobb{}, {5, 5, 5}, GridLayout::node, Interpolation::trilinear);
  const Vec3 face(0.0, 0.13, 0.27);  // x = 0 is a node plane (nodes at -1, -0.5, 0, 0.5, 1)
  const Vec3 left = grid.piece_gradient(face, face - Vec3(0.1, 0, 0));
  const Vec3 right = grid.piece_gradient(face, face + Vec3(0.1, 0, 0));
  EXPECT_NEAR(left.x(), grid.piece_gradient(face - Vec3(1e-12, 0, 0), face - Vec3(1e-12, 0, 0)).x(), 1e-9);
  EXPECT_NEAR(right.x(), grid.piece_gradient(face + Vec3(1e-12, 0, 0), face + Vec3(1e-12, 0, 0)).x(), 1e-9);
  EXPECT_GT(std::abs(left.x() - right.x()), 1e-3);
}

const std::string kShaded = test::unit_box_scene("kind = \"marschner_lobb\"", R"([transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 0.5]]
)") + std::string(test::kPhong) + "normal = \"gradient\"\ntwo_sided = false\n";

TEST(ShadingSceneFile, ReadsEveryKey) {
  const Scene scene = parse_scene(kShaded, "s.toml");
  ASSERT_TRUE(scene.shading);
  const Shading& s = *scene.shading;
  EXPECT_EQ(s.model, ShadingModel::phong);
  EXPECT_EQ(s.ambient, 0.1);
  EXPECT_EQ(s.diffuse, 0.6);
  EXPECT_EQ(s.specular, 0.3);
  EXPECT_EQ(s.shininess, 12.0);
  EXPECT_EQ(*s.light, Vec3(0, 0, 2));
  EXPECT_EQ(s.normal, NormalSign::gradient);
  EXPECT_FALSE(s.two_sided);
  EXPECT_FALSE(default_scene().shading);
}

std::string error_of(std::string_view text) {
  try {
    parse_scene(text, "s.toml");
  } catch (const SceneFileError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ShadingSceneFile, BadValuesNameTheirKey) {
  const std::string base(kShaded.substr(0, kShaded.find("[shading]")));
  EXPECT_EQ(error_of(base + "[shading]\nambient = -0.5\n"), "s.toml: shading.ambient: must be a finite number >= 0, got -0.5");
  EXPECT_EQ(error_of(base + "[shading]\nmodel = \"gouraud\"\n"),
            "s.toml: shading.model: unknown value \"gouraud\" (expected phong or blinn_phong)");
  EXPECT_EQ(error_of(base + "[shading]\nlight = \"sun\"\n").rfind("s.toml: shading.light: unknown value \"sun\"", 0), 0u);
  EXPECT_EQ(error_of(base + "[shading]\ntwo_sided = 1\n"), "s.toml: shading.two_sided: expected true or false, got an integer");
  EXPECT_EQ(error_of(base + "[shading]\nshiny = 3.0\n").rfind("s.toml: shading.shiny: unknown key", 0), 0u);
  EXPECT_EQ(error_of(base + "[shading]\nlight = [0.0, 0.0, 0.0]\n").rfind("s.toml: shading.light: ", 0), 0u);
  const std::string nearest = R"([volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "grid"
resolution = [4, 4, 4]
interpolation = "nearest"
[field.source]
kind = "marschner_lobb"
[transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 0.5]]
[shading]
)";
  EXPECT_EQ(error_of(nearest).rfind("s.toml: shading: a nearest-interpolated grid has no gradient", 0), 0u) << error_of(nearest);
}

TEST(ShadingSceneFile, TheHashCoversTheShading) {
  const Scene a = parse_scene(kShaded, "s.toml");
  Scene b = a;
  b.shading->shininess = 12.5;
  Scene c = a;
  c.shading.reset();
  EXPECT_NE(scene_hash(a), scene_hash(b));
  EXPECT_NE(scene_hash(a), scene_hash(c));
  // Without [shading] the hash is the unshaded file's, as before shading existed.
  EXPECT_EQ(scene_hash(c), scene_hash(parse_scene(kShaded.substr(0, kShaded.find("[shading]")), "s.toml")));
}

// What does not shade yet (verify, export, the studies) refuses a shaded scene by name.
TEST(ShadingRefusal, NamesTheSceneAndWhatDoesNotShade) {
  const Scene scene = parse_scene(kShaded, "s.toml");
  try {
    require_unshaded(scene, "s.toml", "vrv verify");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.toml: shading: the scene shades its emission ([shading]), which vrv verify", 0), 0u)
        << e.what();
  }
  EXPECT_NO_THROW(require_unshaded(default_scene(), "default", "vrv verify"));
}

}  // namespace
}  // namespace vrv::shading_test
