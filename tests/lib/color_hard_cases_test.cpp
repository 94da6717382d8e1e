// Hard cases of RGB scenes (issue 25): a colour jump exactly at a sample, in one channel only.
// The field is the ramp f = x along the ray, so each channel's integral is a closed form: the
// reference must hold it within each channel's own estimate, and every discrete cast of a channel
// must be that channel's grey cast bit for bit (double and float), the jump's sample included.
#include <cmath>
#include <array>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/discrete_channels.h"
#include "lib/discrete_raycast.h"
#include "lib/reference_channels.h"
#include "lib/scene_file.h"

namespace vrv::color_hard_cases_test {

// Red constant; green jumps at f = 0 from 0.2 to 0.9; blue jumps at f = 0.5 from 0.6 to 0.1; one
// constant extinction 1.5.  Background (0.05, 0.1, 0.3).
constexpr const char* kScene = R"(
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "linear_ramp"
gradient = [1.0, 0.0, 0.0]
[transfer]
emission = [[-1.0, 0.5, 0.2, 0.6], [0.0, 0.5, 0.2, 0.6], [0.0, 0.5, 0.9, 0.6], [0.5, 0.5, 0.9, 0.6],
            [0.5, 0.5, 0.9, 0.1], [1.0, 0.5, 0.9, 0.1]]
extinction = [[-1.0, 1.5], [1.0, 1.5]]
[background]
color = [0.05, 0.1, 0.3]
)";

constexpr double kTau = 1.5;

// The ray along +x from x = -2 (entry at t = 1): f(t) = t - 2.
Ray along_x() { return make_ray(Vec3(-2, 0.1, -0.2), Vec3(1, 0, 0)); }

// Channel c's integral over the box, in closed form: constant emission g_k on [a_k, b_k] (in x)
// contributes g_k (e^{-tau (a_k + 1)} - e^{-tau (b_k + 1)}) / tau.
double closed_form(int c) {
  const double g[3][3] = {{0.5, 0.5, 0.5}, {0.2, 0.9, 0.9}, {0.6, 0.6, 0.1}};
  const double edges[4] = {-1.0, 0.0, 0.5, 1.0};
  const double background[3] = {0.05, 0.1, 0.3};
  double sum = 0;
  for (int k = 0; k < 3; ++k)
    sum += g[c][k] * (std::exp(-kTau * (edges[k] + 1)) - std::exp(-kTau * (edges[k + 1] + 1))) / kTau;
  return sum + background[c] * std::exp(-2 * kTau);
}

TEST(ColorHardCases, JumpAtASampleReferenceHoldsTheClosedFormPerChannel) {
  const Scene scene = parse_scene(kScene, "jump_at_sample.toml");
  for (double tol : {1e-12, 1e-9}) {
    const ChannelsReferenceResult r = integrate_color_reference(scene, along_x(), {tol});
    for (int c = 0; c < 3; ++c) {
      const ReferenceResult& ch = r.channel[c];
      EXPECT_TRUE(ch.tolerance_met) << c;
      EXPECT_LE(std::abs(ch.value - closed_form(c)), ch.error_estimate) << fmt::format("channel {} tol {}", c, tol);
      EXPECT_LE(ch.error_estimate, tol) << c;
    }
  }
}

// Channel c as a grey scene written out on its own (not through channel_scene).
std::string grey_scene_text(int c) {
  const double g[6][3] = {{0.5, 0.2, 0.6}, {0.5, 0.2, 0.6}, {0.5, 0.9, 0.6}, {0.5, 0.9, 0.6}, {0.5, 0.9, 0.1}, {0.5, 0.9, 0.1}};
  const double v[6] = {-1.0, 0.0, 0.0, 0.5, 0.5, 1.0};
  std::string points;
  for (int k = 0; k < 6; ++k) points += fmt::format("{}[{}, {}]", k ? ", " : "", v[k], g[k][c]);
  std::string text = kScene;
  text = text.substr(0, text.find("[transfer]"));
  return text + fmt::format("[transfer]\nemission = [{}]\nextinction = [[-1.0, 1.5], [1.0, 1.5]]\n"
                            "[background]\nintensity = {}\n", points, std::array{0.05, 0.1, 0.3}[c]);
}

DiscreteConfig vtk_config(SegmentRule rule, Precision precision) {
  DiscreteConfig config;
  config.rule = rule;
  config.precision = precision;
  config.sampling.strategy = Strategy::vtk;
  config.sampling.step = 0.25;
  return config;
}

// The vtk placement's samples sit at x = -1 + k/4 (t = 1 + k/4, exact in binary): k = 4 is the
// green jump at 0, k = 6 the blue one at 0.5.  Every channel of the RGB scene casts as that
// channel's own grey scene, bit for bit, for every rule and both precisions.
TEST(ColorHardCases, JumpAtASampleDiscreteIsEachChannelsGreySceneBitwise) {
  const Scene scene = parse_scene(kScene, "jump_at_sample.toml");
  for (SegmentRule rule : {SegmentRule::riemann, SegmentRule::alpha, SegmentRule::trapezoid, SegmentRule::exact_linear})
    for (Precision precision : {Precision::double_precision, Precision::single_precision})
      for (int c = 0; c < 3; ++c) {
        const Scene grey = parse_scene(grey_scene_text(c), fmt::format("grey_{}.toml", c));
        const DiscreteConfig config = vtk_config(rule, precision);
        const Ray ray = along_x();
        const double rgb = discrete_channel_values(scene, std::span<const Ray>(&ray, 1), config).front().value[c];
        EXPECT_EQ(rgb, discrete_raycast(grey, along_x(), config).value) << fmt::format("rule {} channel {}",
                                                                                       static_cast<int>(rule), c);
      }
}

// The sample on the jump takes the value above it (right-continuous): green's Riemann sum is
// 0.2 at the three samples before x = 0 and 0.9 from it on (eight samples, the last at x = 1).
TEST(ColorHardCases, TheSampleOnTheJumpTakesTheValueAboveIt) {
  const Scene scene = parse_scene(kScene, "jump_at_sample.toml");
  const DiscreteResult r =
      discrete_raycast(channel_scene(scene, 1), along_x(), vtk_config(SegmentRule::riemann, Precision::double_precision));
  const double h = 0.25;
  double value = 0, transmittance = 1;
  for (int k = 1; k <= 8; ++k) {
    value += transmittance * (k < 4 ? 0.2 : 0.9) * h;
    transmittance *= std::exp(-kTau * h);
  }
  value += transmittance * 0.1;
  EXPECT_EQ(r.samples, 8);
  EXPECT_NEAR(r.value, value, 1e-15);
}

}  // namespace vrv::color_hard_cases_test
