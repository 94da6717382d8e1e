#include "lib/scene_mode.h"

#include <gtest/gtest.h>

#include "lib/scene_file.h"

namespace vrv {
namespace {

const std::string kBody = std::string(default_scene_toml());

TEST(SceneMode, ReadFromTheSceneText) {
  EXPECT_FALSE(scene_mode(kBody));
  EXPECT_EQ(scene_mode("mode = \"xray\"\n" + kBody), ProjectionMode::xray);
  EXPECT_EQ(scene_mode("mode = \"mip_classified\"\n" + kBody), ProjectionMode::mip_classified);
}

TEST(SceneMode, TheCommandLineOverridesTheScene) {
  const std::string mip = "mode = \"mip\"\n" + kBody;
  EXPECT_EQ(chosen_mode("", mip), "mip");
  EXPECT_EQ(chosen_mode("xray", mip), "xray");
  EXPECT_EQ(chosen_mode(kEmissionAbsorption, mip), "");  // back to emission-absorption
  EXPECT_EQ(chosen_mode("", kBody), "");
  EXPECT_EQ(chosen_mode("nonsense", kBody), "nonsense");  // the command refuses it, naming --mode
}

}  // namespace
}  // namespace vrv
