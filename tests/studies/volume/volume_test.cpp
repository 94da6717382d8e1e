// The volume study (studies/volume/driver.cpp): its reading refuses what it cannot measure, one
// line naming the key.  Its --quick run, with the order checks as the gate, is CTest's
// study.volume.quick; study.volume.tightened shows that gate failing.
#include <gtest/gtest.h>

#include <string>

#include "lib/study_file.h"
#include "studies/engine/study_driver.h"

namespace vrv {
namespace {

constexpr const char* kImages =
    "kind = \"volume\"\n"
    "[images]\nstrategy = \"inviwo\"\nreference_tol = 1e-11\n"
    "order_tolerance = { margin = 2.0, floor = 0.05 }\n"
    "[[images.rule]]\nrule = \"trapezoid\"\nexpected_order = 2\n";

constexpr const char* kRender =
    "[render]\nname = \"scan\"\nsteps = [1.0, 0.5, 0.25]\nquick_steps = [1.0, 0.5, 0.25]\nmap_step = 1.0\n"
    "quick_width = 8\nquick_height = 8\n"
    "[render.scene.transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 1]]\n"
    "[render.scene.camera]\neye = [0, 0, -5]\ntarget = [0, 0, 0]\nup = [0, 1, 0]\nfov = 40\n"
    "width = 16\nheight = 16\n";

// The error's one line, or "accepted".
std::string refusal(const std::string& text) {
  const StudyParse parse = find_study_kind("volume");
  if (!parse) return "no study kind 'volume'";
  const StudyReader r("bad.toml");
  const toml::table doc = parse_study_toml(text, "bad.toml");
  try {
    parse(StudyInput{doc, r, "volume"});
    return "accepted";
  } catch (const StudyFileError& e) {
    return e.what();
  }
}

TEST(VolumeStudy, RefusesAFieldThatIsNotAVolumeFile) {
  const std::string text = std::string(kImages) + kRender +
                           "[render.scene.volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
                           "[render.scene.field]\nkind = \"grid\"\nresolution = [5, 5, 5]\n"
                           "[render.scene.field.source]\nkind = \"marschner_lobb\"\n";
  const std::string why = refusal(text);
  EXPECT_NE(why.find("bad.toml: render.scene.field"), std::string::npos) << why;
  EXPECT_NE(why.find("kind = \"volume\""), std::string::npos) << why;
}

TEST(VolumeStudy, RefusesAnUnknownKeyNamingIt) {
  const std::string text = "rays = 4\n" + std::string(kImages) + kRender;
  const std::string why = refusal(text);
  EXPECT_NE(why.find("rays"), std::string::npos) << why;
}

TEST(VolumeStudy, RefusesASamplingStrategyThatIsNotStepBased) {
  std::string text = std::string(kImages) + kRender;
  text.replace(text.find("\"inviwo\""), 8, "\"voxel\"");
  const std::string why = refusal(text);
  EXPECT_NE(why.find("images.strategy"), std::string::npos) << why;
}

}  // namespace
}  // namespace vrv
