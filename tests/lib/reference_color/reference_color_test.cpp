// The RGB reference (lib/reference_channels.h) on rays with an independent mpmath truth per channel
// (make_color_truth.py, same folder: the adversarial generator's integrator run on each channel
// alone).  On every ray, at tol 1e-12 and 1e-10, for every channel:
//   honest:     |value - truth| <= error_estimate, both finite;
//   not absurd: error_estimate <= max(100 max(|error|, floor), tol) (the adversarial test's rule);
//   shared:     the RGB ray's field evaluations are at most kSharedEvaluations x those of its
//               costliest channel integrated alone (the panels are fitted once for three).
// And: three equal channels give the grey value and estimate bit for bit; a grey scene is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/reference_channels.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"
#include "lib/scene_file.h"
#include "tests/lib/truth_lines.h"

namespace vrv::reference_color_test {
namespace {

struct ChannelTruth {
  long double truth = 0;
  std::string text;
  double floor = 0;
};

struct ColorRay {
  std::string cls, tag, scene_toml;
  Vec3 origin, direction;
  std::vector<ChannelTruth> channels;
  std::vector<double> grid_nodes;
};

const std::vector<ColorRay>& rays() {
  static const std::vector<ColorRay> all = [] {
    std::vector<ColorRay> out;
    for (const nlohmann::json& j : test::truth_lines("tests/lib/reference_color/color_rays.jsonl")) {
      ColorRay r;
      r.cls = j["class"];
      r.tag = j["tag"];
      r.scene_toml = j["scene"];
      r.origin = test::hex_vec3(j["origin"]);
      r.direction = test::hex_vec3(j["direction"]);
      for (const auto& c : j["channels"]) {
        const std::string text = c["truth"];
        r.channels.push_back({std::strtold(text.c_str(), nullptr), text, c["floor"]});
      }
      if (j.contains("grid_nodes"))
        for (const auto& v : j["grid_nodes"]) r.grid_nodes.push_back(test::hex_double(v));
      out.push_back(std::move(r));
    }
    return out;
  }();
  return all;
}

// The shared panels are refined for the most demanding channel; the other two ride along.
constexpr double kSharedEvaluations = 1.3;

TEST(ColorReference, DataCoverEveryClass) {
  std::vector<std::string> classes;
  for (const ColorRay& r : rays()) {
    ASSERT_EQ(r.channels.size(), 3u) << r.tag;
    classes.push_back(r.cls);
  }
  for (const char* c : {"channel_jumps", "extremum_jump", "opacity_color", "thick", "dark_channel", "grid", "miss"})
    EXPECT_NE(std::find(classes.begin(), classes.end(), c), classes.end()) << c;
}

TEST(ColorReference, GridNodesAreTheTruthsNodes) {
  for (const ColorRay& r : rays()) {
    if (!r.grid_nodes.empty()) test::expect_grid_nodes_are_the_truths(r.scene_toml, r.grid_nodes, r.tag);
  }
}

void check_against_truth(double tol) {
  int checked = 0;
  for (const ColorRay& r : rays()) {
    const Scene scene = parse_scene(r.scene_toml, r.tag);
    ASSERT_TRUE(scene.color) << r.tag;
    const Ray ray = make_ray(r.origin, r.direction);
    const ChannelsReferenceResult rgb = integrate_color_reference(scene, ray, {tol});
    long alone = 0;
    for (int c = 0; c < 3; ++c) {
      const ReferenceResult& res = rgb.channel[c];
      const ChannelTruth& truth = r.channels[c];
      const long double error = static_cast<long double>(res.value) - truth.truth;
      const double bound = std::max(100 * std::max(static_cast<double>(std::fabs(error)), truth.floor), tol);
      const bool finite = std::isfinite(res.value) && std::isfinite(res.error_estimate);
      EXPECT_TRUE(finite && std::fabs(error) <= static_cast<long double>(res.error_estimate))
          << fmt::format("[{} | {}] channel {} tol {:.0e}: DISHONEST value {:.17g} truth {} error {:.3Le} estimate {:.3e}",
                         r.cls, r.tag, c, tol, res.value, truth.text, error, res.error_estimate);
      EXPECT_LE(res.error_estimate, bound)
          << fmt::format("[{} | {}] channel {} tol {:.0e}: ABSURD estimate {:.3e}, error {:.3Le}, floor {:.3g}",
                         r.cls, r.tag, c, tol, res.error_estimate, error, truth.floor);
      alone = std::max(alone, integrate_reference(channel_scene(scene, c), ray, {tol}).evaluations);
      ++checked;
    }
    EXPECT_LE(rgb.evaluations, kSharedEvaluations * alone)
        << fmt::format("[{} | {}] tol {:.0e}: {} evaluations for RGB, {} for the costliest channel alone", r.cls,
                       r.tag, tol, rgb.evaluations, alone);
  }
  EXPECT_EQ(checked, 3 * static_cast<int>(rays().size()));
}

TEST(ColorReference, HonestAndNotAbsurdPerChannelAtTol1em12) { check_against_truth(1e-12); }
TEST(ColorReference, HonestAndNotAbsurdPerChannelAtTol1em10) { check_against_truth(1e-10); }

// Three copies of a grey transfer function: each channel is the grey ray, bit for bit (the shared
// panels are the grey ray's when every channel asks for the same).
TEST(ColorReference, EqualChannelsAreTheGreyRayBitwise) {
  for (const ColorRay& r : rays()) {
    Scene grey = channel_scene(parse_scene(r.scene_toml, r.tag), 1);
    Scene rgb = grey;
    rgb.color = ColorChannels{{grey.transfer, grey.transfer, grey.transfer}, {grey.background, grey.background, grey.background}};
    const Ray ray = make_ray(r.origin, r.direction);
    for (double tol : {1e-12, 1e-10}) {
      const ReferenceResult one = integrate_reference(grey, ray, {tol});
      const ChannelsReferenceResult three = integrate_color_reference(rgb, ray, {tol});
      EXPECT_EQ(three.evaluations, one.evaluations) << r.tag;
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(three.channel[c].value, one.value) << r.tag << " channel " << c;
        EXPECT_EQ(three.channel[c].error_estimate, one.error_estimate) << r.tag << " channel " << c;
        EXPECT_EQ(three.channel[c].tolerance_met, one.tolerance_met) << r.tag << " channel " << c;
      }
    }
  }
}

TEST(ColorReference, AGreySceneIsRefused) {
  EXPECT_THROW(integrate_color_reference(default_scene(), make_ray(Vec3(0, 0, -5), Vec3(0, 0, 1))),
               std::invalid_argument);
}

}  // namespace
}  // namespace vrv::reference_color_test
