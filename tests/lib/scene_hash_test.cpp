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

}  // namespace
}  // namespace vrv
