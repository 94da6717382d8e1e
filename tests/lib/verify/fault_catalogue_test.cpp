// lib/verify/fault_fit: an honest score for the fitted fault catalogue.  A toy renderer that is not
// vrv's (tests/lib/toy_raycaster.h, toy::Planted) with one step-independent fault planted at a
// time must be named by that fault's class, with the fitted parameter near the planted one; the
// correct toy of each common placement names no fault (conventions_test.cpp).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "lib/verify/fault_fit.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv::verify_toy {
namespace {

// A transfer function with interior breakpoints and emission off zero, so that reading it at a
// scaled value differs from scaling its opacity.
constexpr const char* kTransfer = R"(
[transfer]
emission = [[0.0, 0.1], [0.6, 0.5], [1.0, 1.0]]
extinction = [[0.0, 0.2], [0.4, 0.6], [1.0, 2.0]]
)";

std::string scene_text(bool grid) {
  std::string text = kScene;
  const std::string from = "[transfer]\nemission = [[0.0, 0.0], [1.0, 1.0]]\nextinction = [[0.0, 0.0], [1.0, 2.0]]\n";
  text.replace(text.find(from), from.size(), std::string(kTransfer).substr(1));
  if (grid) {
    const std::string field = "[field]\nkind = \"marschner_lobb\"\n";
    text.replace(text.find(field), field.size(),
                 "[field]\nkind = \"grid\"\nresolution = [17, 17, 17]\nlayout = \"node\"\n"
                 "interpolation = \"trilinear\"\n[field.source]\nkind = \"marschner_lobb\"\n");
  }
  return text;
}

struct Case {
  std::string name;     // the test's name and the expected entry's id
  toy::Planted planted;
  double parameter;     // the planted value of the entry's parameter (NaN: none)
  double tolerance;     // how near the fit must come
  bool grid = false;
};

class FaultCatalogue : public ::testing::TestWithParam<Case> {};

TEST_P(FaultCatalogue, PlantedFaultIsNamedWithItsParameter) {
  const Case& c = GetParam();
  const Scene scene = parse_scene(scene_text(c.grid), "catalogue.toml");
  const auto images = images_in_memory(
      scene, [&](double h) { return toy::render(scene, *scene.camera, h, c.planted); }, c.name);
  const VerifyReport r = verify_images(scene, images, options());
  EXPECT_FALSE(r.pass);
  ASSERT_FALSE(r.fault_fits.empty()) << verdict_name(r.verdict.verdict) << ": " << r.verdict.reason;
  const FaultFit& best = r.fault_fits.front();
  for (const FaultFit& f : r.fault_fits)
    std::cout << c.name << ": " << f.id << " " << f.value << " explains " << f.explained << " confirmed "
              << f.confirmed << "\n";
  EXPECT_EQ(best.id, c.name) << best.description;
  if (std::isfinite(c.parameter)) {
    EXPECT_NEAR(best.value, c.parameter, c.tolerance) << best.description;
  }
  EXPECT_GE(best.confirmed, kNamedFraction);
  ASSERT_TRUE(has_fault(r, FaultKind::fitted));
  const auto named = std::find_if(r.faults.begin(), r.faults.end(), [](const Fault& f) { return f.kind == FaultKind::fitted; });
  EXPECT_EQ(named->behaviour, best.description);
}

toy::Planted planted(void (*set)(toy::Planted&)) {
  toy::Planted p;
  set(p);
  return p;
}

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

INSTANTIATE_TEST_SUITE_P(
    Toy, FaultCatalogue,
    ::testing::Values(
        Case{"rows_flipped", planted([](toy::Planted& p) { p.flip_rows = true; }), kNone, 0},
        Case{"columns_flipped", planted([](toy::Planted& p) { p.flip_columns = true; }), kNone, 0},
        Case{"transposed", planted([](toy::Planted& p) { p.transpose = true; }), kNone, 0},
        Case{"srgb", planted([](toy::Planted& p) { p.srgb = true; }), kNone, 0},
        Case{"gamma", planted([](toy::Planted& p) { p.gamma = 1.8; }), 1.8, 0.02},
        Case{"fov_scale", planted([](toy::Planted& p) { p.fov_scale = 1.02; }), 1.02, 0.002},
        Case{"tf_domain_scale", planted([](toy::Planted& p) { p.tf_scale = 255.0 / 256; }), 255.0 / 256, 5e-4},
        Case{"tf_domain_offset", planted([](toy::Planted& p) { p.tf_offset = 1.0 / 255; }), 1.0 / 255, 5e-4},
        Case{"termination", planted([](toy::Planted& p) { p.termination = 0.5; }), 0.5, 0.02},
        Case{"opacity_step_ratio", planted([](toy::Planted& p) { p.opacity_ratio = 2; }), 2, 0.02},
        Case{"nearest", planted([](toy::Planted& p) { p.nearest = true; }), kNone, 0, true},
        Case{"box_offset", planted([](toy::Planted& p) { p.box_grow = 0.5; }), 0.5, 0.05, true},
        Case{"tf_bits", planted([](toy::Planted& p) { p.table_bits = 8; }), 8, 0},
        Case{"pixel_shift", planted([](toy::Planted& p) { p.pixel_shift = -0.5; }), -0.5, 0.02}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace vrv::verify_toy
