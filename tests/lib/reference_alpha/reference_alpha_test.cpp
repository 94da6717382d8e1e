// The alpha channel of the reference (lib/reference_channels.h ImageChannels): the transmittance
// e^-Phi of a zero-emission channel over a background of 1, so A = 1 - its value, against the
// independent mpmath optical depth of the adversarial rays (325 rays in 20 classes: huge and tiny
// depth, far origins, grazing and corner rays, grids, jumps near extrema) and of the colour rays
// (27 rays).  The truths are the generators' Phi (make_adversarial.py, make_color_truth.py: their own
// root finding and quadrature at 40 digits), stored as doubles: T* = e^-Phi* to within
// e^-Phi* Phi* eps.  Where the generator stopped the ray (the rest below 1e-45) T* lies in
// [0, e^-Phi*].  On every ray, at tol 1e-12 and 1e-10:
//   honest:     the distance from T to the truth is at most T's estimate, both finite;
//   not absurd: the estimate is at most max(100 max(distance, floor), tol), the floor being the
//               largest of the truth's storage rounding, 8 eps (1 + Phi) T* (the rounding of
//               e^-Phi) and the ray's own floor for I (the generators' field-rounding sensitivity,
//               pointwise bound and rounding; a colour ray's largest channel's).  The generators
//               give no floor for T itself; I's floor stands in for it, being set on these rays by
//               the same extinction (its jumps near extrema: T's estimate there is 2.9e-12 and
//               4.1e-12 at tol 1e-12, for errors of 1e-14, where I's floors are 2e-13 and 2e-11).
// And: a scene whose emission is g = tau (opacity-colour with colour 1, background 0) has I = A;
// adding alpha leaves a channel's tolerance met.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/reference_channels.h"
#include "lib/scene.h"
#include "lib/scene_file.h"
#include "tests/lib/scene_text.h"
#include "tests/lib/truth_lines.h"

namespace vrv::reference_alpha_test {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

struct DepthRay {
  std::string file, cls, tag, scene_toml;
  Vec3 origin, direction;
  bool hit = false, stopped = false;
  double optical_depth = 0;
  double floor = 0;  // the ray's floor for I (a colour ray's: the largest of its channels')
};

std::vector<DepthRay> depth_rays() {
  std::vector<DepthRay> out;
  for (const char* file : {"tests/lib/reference_adversarial/adversarial_rays.jsonl",
                           "tests/lib/reference_color/color_rays.jsonl"}) {
    const bool colour = std::string(file).find("color") != std::string::npos;
    for (const nlohmann::json& j : test::truth_lines(file)) {
      DepthRay r;
      r.file = file;
      r.cls = j["class"];
      r.tag = j["tag"];
      r.scene_toml = j["scene"];
      r.origin = test::hex_vec3(j["origin"]);
      r.direction = test::hex_vec3(j["direction"]);
      r.hit = j.value("hit", true);
      r.stopped = j.value("stopped", false);
      r.optical_depth = colour ? j["channels"][0]["optical_depth"].get<double>() : j["optical_depth"].get<double>();
      if (colour)
        for (const auto& c : j["channels"]) r.floor = std::max(r.floor, c["floor"].get<double>());
      else if (r.hit)
        r.floor = j["floor"];
      out.push_back(std::move(r));
    }
  }
  return out;
}

const std::vector<DepthRay>& rays() {
  static const std::vector<DepthRay> all = depth_rays();
  return all;
}

TEST(AlphaReference, DataHoldDepthsOfBothSets) {
  long grey = 0, colour = 0, thick = 0;
  for (const DepthRay& r : rays()) {
    (r.file.find("color") != std::string::npos ? colour : grey) += 1;
    if (r.optical_depth > 30) ++thick;
  }
  EXPECT_EQ(grey, 332);
  EXPECT_EQ(colour, 27);
  EXPECT_GE(thick, 10);
}

// The transmittance channel of `scene` along the ray (its last channel).
ReferenceResult transmittance(const Scene& scene, const Ray& ray, double tol) {
  const ImageChannels channels(scene, true);
  const ChannelsReferenceResult r = visit_field(scene, [&](const auto& field) {
    return integrate_channels_reference(field, scene.box, channels.channels(), ray, {tol}, scene.shading_or_null());
  });
  return r.channel[r.count - 1];
}

void check_against_truth(double tol) {
  int checked = 0, dishonest = 0, absurd = 0;
  for (const DepthRay& r : rays()) {
    const Scene scene = parse_scene(r.scene_toml, r.tag);
    const ReferenceResult t = transmittance(scene, make_ray(r.origin, r.direction), tol);
    const double truth = r.hit ? std::exp(-r.optical_depth) : 1.0;
    // Stopped: the truth is anywhere in [0, e^-Phi*] (Phi* is then a lower bound).
    const double lo = r.stopped ? 0.0 : truth, hi = truth;
    const double distance = t.value < lo ? lo - t.value : t.value > hi ? t.value - hi : 0.0;
    const double floor = std::max({truth * r.optical_depth * eps, 8 * eps * (1 + r.optical_depth) * truth, r.floor});
    const bool finite = std::isfinite(t.value) && std::isfinite(t.error_estimate);
    const bool honest = finite && distance <= t.error_estimate;
    const bool sensible = t.error_estimate <= std::max(100 * std::max(distance, floor), tol);
    dishonest += !honest, absurd += !sensible;
    EXPECT_TRUE(honest) << fmt::format("[{} | {}] tol {:.0e}: DISHONEST T {:.17g}, truth e^-{:.17g} = {:.17g}{}, "
                                       "distance {:.3e}, estimate {:.3e}", r.cls, r.tag, tol, t.value,
                                       r.optical_depth, truth, r.stopped ? " (or less: stopped)" : "", distance,
                                       t.error_estimate);
    EXPECT_TRUE(sensible) << fmt::format("[{} | {}] tol {:.0e}: ABSURD estimate {:.3e}, distance {:.3e}, floor {:.3e}",
                                         r.cls, r.tag, tol, t.error_estimate, distance, floor);
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(rays().size()));
  std::cout << fmt::format("alpha at tol {:.0e}: {} rays, {} dishonest, {} absurd\n", tol, checked, dishonest, absurd);
}

TEST(AlphaReference, HonestAndNotAbsurdAtTol1em12) { check_against_truth(1e-12); }
TEST(AlphaReference, HonestAndNotAbsurdAtTol1em10) { check_against_truth(1e-10); }

// Colour 1 in the opacity-colour convention makes g = tau, so I = 1 - e^-Phi = A over a black
// background: the colour and alpha channels, integrated differently (emission against depth
// alone), agree within their estimates.
TEST(AlphaReference, WhiteEmissionEqualsAlpha) {
  const Scene scene = parse_scene(test::unit_box_scene("kind = \"marschner_lobb\"", R"([transfer]
opacity = [[0.0, 0.0], [0.3, 0.05], [0.5, 0.6], [0.5, 0.2], [1.0, 0.9]]
color = [[0.0, 1.0]]
unit_length = 0.05
)"), "white");
  int checked = 0;
  for (double x : {-0.7, -0.2, 0.1, 0.45})
    for (double y : {-0.6, 0.0, 0.35}) {
      const Ray ray = make_ray(Vec3(x, y, -3), Vec3(0.1, -0.05, 1).normalized());
      const ImageChannels channels(scene, true);
      const ChannelsReferenceResult r = visit_field(scene, [&](const auto& field) {
        return integrate_channels_reference(field, scene.box, channels.channels(), ray, {1e-12});
      });
      ASSERT_EQ(r.count, 2);
      const double a = 1 - r.channel[1].value;
      EXPECT_NEAR(r.channel[0].value, a, r.channel[0].error_estimate + r.channel[1].error_estimate) << x << ' ' << y;
      EXPECT_TRUE(r.tolerance_met());
      EXPECT_GT(a, 0.1) << "the ray should absorb";
      ++checked;
    }
  EXPECT_EQ(checked, 12);
}

// A homogeneous medium along an axis (opacity alpha per unit length over a chord of length 2, so
// T = (1 - alpha)^2) where T is small has T's estimate far below an ulp of 1: then the rounding
// of A = 1 - T itself (up to half an ulp of A, not of T) is most of A's error and must be in its
// estimate.  The truth: 1 - (1 - alpha)^2 in long double.
TEST(AlphaReference, TheTurningOverIsInTheEstimate) {
  int checked = 0;
  for (double alpha : {0.3, 0.9, 0.99, 0.999, 0.99999, 0.9999999, 1 - 1e-9}) {
    const Scene scene = parse_scene(test::unit_box_scene("kind = \"linear_ramp\"\ngradient = [0.0, 0.0, 0.0]\noffset = 0.5",
                                                         fmt::format("[transfer]\nopacity = [[0.0, {0:.17g}], [1.0, {0:.17g}]]\n"
                                                                     "color = [[0.0, 0.4], [1.0, 0.4]]\n", alpha)),
                                    "homogeneous");
    for (double x : {-0.31, 0.0, 0.27}) {
      const Ray ray = make_ray(Vec3(x, 0.13, -3), Vec3(0, 0, 1));
      const ImageChannels channels(scene, true);
      const ChannelsReferenceResult r = visit_field(scene, [&](const auto& field) {
        return integrate_image_channels(field, scene.box, channels, ray, {1e-12});
      });
      ASSERT_EQ(r.count, 2);
      const ReferenceResult& a = r.channel[1];
      const long double truth = 1 - (1 - static_cast<long double>(alpha)) * (1 - static_cast<long double>(alpha));
      const double distance = static_cast<double>(std::fabs(static_cast<long double>(a.value) - truth));
      EXPECT_LE(distance, a.error_estimate) << fmt::format("alpha {} x {}: A {:.17g}, truth {:.20Lg}, estimate {:.3e}",
                                                           alpha, x, a.value, truth, a.error_estimate);
      EXPECT_TRUE(a.tolerance_met);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 21);
}

// With alpha the colour is over nothing: the channels' background is 0, whatever the scene's.
TEST(AlphaReference, ColourIsOverNothing) {
  Scene scene = default_scene();
  scene.background = 0.25;
  const ImageChannels plain(scene, false), with_alpha(scene, true);
  ASSERT_EQ(plain.count(), 1);
  ASSERT_EQ(with_alpha.count(), 2);
  EXPECT_EQ(plain.channels()[0].background, 0.25);
  EXPECT_EQ(with_alpha.channels()[0].background, 0.0);
  EXPECT_EQ(with_alpha.channels()[1].background, 1.0);
  EXPECT_EQ(with_alpha.channels()[1].transfer->max_emission(), 0.0);
}

}  // namespace
}  // namespace vrv::reference_alpha_test
