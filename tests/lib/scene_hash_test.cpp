#include "lib/scene_hash.h"

#include <gtest/gtest.h>

#include "lib/scene_file.h"

namespace vrv {
namespace {

TEST(SceneHash, SameSceneSameHashAndEveryIngredientChangesIt) {
  const Scene s = default_scene();
  const Camera c = default_camera(s.box);
  const std::string h = scene_hash(s, c);
  EXPECT_EQ(h.size(), 40u);
  EXPECT_EQ(h, scene_hash(default_scene(), default_camera(s.box)));
  EXPECT_NE(h, scene_hash(s));

  Camera wider = c;
  wider.width += 1;
  EXPECT_NE(h, scene_hash(s, wider));
  Camera turned = c;
  turned.eye[0] = std::nextafter(turned.eye[0], 1.0);  // one ulp
  EXPECT_NE(h, scene_hash(s, turned));

  Scene lit = s;
  lit.background = 0.5;
  EXPECT_NE(scene_hash(s), scene_hash(lit));
  Scene ramp = s;
  ramp.field = LinearRamp{};
  EXPECT_NE(scene_hash(s), scene_hash(ramp));

  Scene g1 = s, g2 = s;
  g1.field = make_grid(s.box, MarschnerLobb{}, {4, 4, 4}, GridLayout::node, Interpolation::trilinear);
  g2.field = make_grid(s.box, MarschnerLobb{0.9 * 6}, {4, 4, 4}, GridLayout::node, Interpolation::trilinear);
  EXPECT_NE(scene_hash(g1), scene_hash(g2));  // node values enter the hash
}

// A hash is a cache key and an image's provenance: a refactor must not change it.  These are the
// hashes `vrv render --reference --width 2 --height 2 [--scene ramp.toml]` wrote before the
// analytic fields declared their own kind and parameters (lib/scene_hash.cpp, analytic/*.h).
TEST(SceneHash, AnalyticFieldsHashAsBefore) {
  const auto hash_2x2 = [](const Scene& s) {
    Camera c = default_camera(s.box);
    c.width = c.height = 2;
    return scene_hash(s, c);
  };
  EXPECT_EQ(hash_2x2(default_scene()), "b8c10bd940bc37f98593bf3578a393b1bd12e041");
  const Scene ramp = parse_scene(
      "[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
      "[field]\nkind = \"linear_ramp\"\ngradient = [0.25, -0.5, 0.125]\noffset = 0.5\n"
      "[transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 2]]\n",
      "ramp.toml");
  EXPECT_EQ(hash_2x2(ramp), "4a7527bd308d989c716bbaaa9485cce28bcfb7b0");
}

}  // namespace
}  // namespace vrv
