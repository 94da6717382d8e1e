// lib/verify/diagnosis and model_catalogue: the diagnosis names the convention a renderer reads
// its transfer function with: a toy renderer (tests/lib/toy_renderer_conventions.h, not vrv's raycaster) on an opacity/colour scene, with the
// opacity per unit distance corrected to the sample distance, premultiplied colour, and N-entry
// tables read with and without half-texel centring; each image set's nearest model is that one.
#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/scene_file.h"
#include "lib/verify.h"
#include "tests/lib/toy_renderer_conventions.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv {
namespace {

// Breakpoints off every table entry (0.3 x 255 = 76.5, 0.55 x 1023 = 562.65, ...), so that a
// centred table differs from the curve itself; a grey background, so that colour shows.
constexpr const char* kScene = R"(
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[transfer]
opacity = [[0.0, 0.0], [0.3, 0.05], [1.0, 0.6]]
color = [[0.0, 0.2], [0.55, 1.0], [1.0, 0.5]]
unit_length = 0.25
[background]
intensity = 0.1
[camera]
eye = [1.5, 1.0, -4.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 40.0
width = 20
height = 20
)";

// The toy's images in double, as a renderer's in-memory images (no file quantisation).
std::vector<ImageWithStep> images(const Scene& scene, const toy::RendererConvention& c) {
  return verify_toy::images_in_memory(
      scene, [&](double h) { return toy::render(scene, *scene.camera, h, c); }, "toy", verify_toy::kThreeSteps);
}

struct Case {
  toy::RendererConvention convention;
  std::string color, table;
};

class VerifyDiagnosis : public ::testing::TestWithParam<Case> {};

TEST_P(VerifyDiagnosis, NearestModelIsTheRenderersConvention) {
  const Scene scene = parse_scene(kScene, "conventions.toml");
  const Case& c = GetParam();
  const VerifyReport r = verify_images(scene, images(scene, c.convention), {});
  ASSERT_GE(r.diagnosis.size(), 2u);
  const Candidate& best = r.diagnosis.front();
  EXPECT_EQ(best.placement, "inviwo") << best.name;
  EXPECT_EQ(best.rule, "alpha") << best.name;
  EXPECT_NE(best.opacity.find("per unit distance L = 0.25 corrected to the sample distance"), std::string::npos)
      << best.name;
  EXPECT_EQ(best.color, c.color) << best.name;
  EXPECT_EQ(best.table, c.table) << best.name;
  // The same arithmetic up to rounding, and far from every other model.
  EXPECT_LT(best.rms, 1e-13) << best.name;
  EXPECT_GT(r.diagnosis[1].rms, 1e4 * best.rms) << r.diagnosis[1].name;
  EXPECT_GT(r.diagnosis[1].rms, 1e-7) << r.diagnosis[1].name;
}

INSTANTIATE_TEST_SUITE_P(
    Conventions, VerifyDiagnosis,
    ::testing::Values(Case{{}, "straight", "none"},
                      Case{{.premultiplied = true}, "premultiplied", "none"},
                      Case{{.table_size = 256, .centred = true}, "straight", "256 centred"},
                      Case{{.table_size = 256, .centred = false}, "straight", "256 uncentred"},
                      Case{{.table_size = 1024, .centred = true}, "straight", "1024 centred"},
                      Case{{.table_size = 1024, .centred = false}, "straight", "1024 uncentred"}),
    [](const ::testing::TestParamInfo<Case>& info) {
      std::string name = info.param.color + "_" + info.param.table;
      std::replace(name.begin(), name.end(), ' ', '_');
      return name;
    });

// Without its opacity correction (the opacity per unit distance taken per sample), the nearest
// model is the uncorrected one and the fault is named.
TEST(VerifyDiagnosisFaults, OpacityPerSampleIsMissingCorrection) {
  const Scene scene = parse_scene(kScene, "conventions.toml");
  std::vector<ImageWithStep> ims;
  for (double h : verify_toy::kThreeSteps) {
    DiscreteConfig config;
    config.rule = SegmentRule::alpha;
    config.sampling.strategy = Strategy::inviwo;
    config.sampling.step = h;
    ChannelImage im(ImageF64(20, 20, discrete_image(scene, *scene.camera, config)));
    ims.push_back({fmt::format("per_sample_{}", h), h, std::move(im)});
  }
  const VerifyReport r = verify_images(scene, ims, {});
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_FALSE(r.diagnosis.front().opacity_corrected) << r.diagnosis.front().name;
  bool named = false;
  for (const Fault& f : r.faults) named = named || f.kind == FaultKind::missing_opacity_correction;
  EXPECT_TRUE(named);
}

TEST(VerifyDiagnosisFaults, BadTableSizeIsRefused) {
  const Scene scene = parse_scene(kScene, "conventions.toml");
  VerifyOptions o;
  o.table_sizes = {1};
  EXPECT_THROW(verify_images(scene, images(scene, {}), o), std::invalid_argument);
}

}  // namespace
}  // namespace vrv
