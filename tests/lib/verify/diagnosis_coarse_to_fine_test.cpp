// lib/verify/diagnosis, coarse to fine (issue 23): repeated configurations are dropped before any
// cast, and only where the cast would have dropped them; the leaders' numbers are those of every
// diagnosis pixel, bit for bit; the report does not depend on the thread count; and the work
// estimate counts what is cast.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "lib/scene_file.h"
#include "lib/util/parallel.h"
#include "lib/verify.h"
#include "lib/verify/model_catalogue.h"
#include "lib/work_estimate.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv {
namespace {

// The toy scene (verify_toy.h: a ramp transfer function, breakpoints 0 and 1 on every entry of
// any centred table) on a 40 x 40 camera: 1600 pixels, so the ranking lattice (about 1024) is
// smaller than the diagnosis's.
std::string ramp_scene_text() {
  std::string text = verify_toy::kScene;
  for (const std::string key : {"width = ", "height = "}) text.replace(text.find(key + "32"), key.size() + 2, key + "40");
  return text;
}

Scene ramp_scene() { return parse_scene(ramp_scene_text(), "ramp.toml"); }

// vrv's own trapezoid images (inviwo placement) of the scene.
std::vector<ImageWithStep> trapezoid_images(const Scene& scene) {
  std::vector<ImageWithStep> out;
  for (double h : verify_toy::kThreeSteps) {
    DiscreteConfig config;
    config.rule = SegmentRule::trapezoid;
    config.sampling.strategy = Strategy::inviwo;
    config.sampling.step = h;
    ChannelImage im(ImageF64(scene.camera->width, scene.camera->height, discrete_image(scene, *scene.camera, config)));
    im.pixel_type = "double";
    out.push_back({fmt::format("trapezoid_{}", h), h, std::move(im)});
  }
  return out;
}

std::vector<const ImageWithStep*> pointers(const std::vector<ImageWithStep>& images) { return sorted_by_step(images); }

// Every pixel's largest difference between two models' casts, against 1e-11 of the largest value:
// the rule by which the diagnosis drops a model that repeats another.
bool cast_alike(const Scene& scene, const Model& a, const Model& b) {
  const std::vector<long> pixels = diagnosis_pixels(scene.camera->width, scene.camera->height);
  double scale = 1, diff = 0;
  for (std::size_t k = 0; k < a.per_step.size(); ++k) {
    const std::vector<double> x = cast_pixels(scene, *scene.camera, a.per_step[k], pixels);
    const std::vector<double> y = cast_pixels(scene, *scene.camera, b.per_step[k], pixels);
    for (std::size_t j = 0; j < x.size(); ++j)
      scale = std::max(scale, std::abs(x[j])), diff = std::max(diff, std::abs(x[j] - y[j]));
  }
  return diff <= 1e-11 * scale;
}

TEST(DiagnosisCoarseToFine, RepeatedConfigurationsAreDroppedBeforeCastingAndOnlyThose) {
  const Scene scene = ramp_scene();
  const std::vector<Model> all = model_catalogue(scene, verify_toy::kThreeSteps, {});
  const std::vector<Model> distinct = distinct_models(scene, verify_toy::kThreeSteps, {});
  // The centred 256- and 1024-entry tables at five placements read the ramp itself.
  EXPECT_EQ(all.size() - distinct.size(), 10u);
  for (const Model& m : all) {
    const auto kept = std::find_if(distinct.begin(), distinct.end(), [&](const Model& d) { return same_model(d, m, scene); });
    ASSERT_NE(kept, distinct.end()) << m.label.name;
    if (kept->label.name == m.label.name) continue;
    EXPECT_EQ(m.label.table.find("uncentred"), std::string::npos) << m.label.name;
    EXPECT_TRUE(cast_alike(scene, *kept, m)) << m.label.name << " vs " << kept->label.name;
  }
  // Breakpoints off the entries (0.3 x 255 = 76.5): every table is its own model.
  std::string off_text = ramp_scene_text();
  off_text.replace(off_text.find("[1.0, 1.0]]"), 11, "[0.3, 0.2], [1.0, 1.0]]");
  const Scene off = parse_scene(off_text, "off.toml");
  EXPECT_EQ(distinct_models(off, verify_toy::kThreeSteps, {}).size(), model_catalogue(off, verify_toy::kThreeSteps, {}).size());
}

TEST(DiagnosisCoarseToFine, LeadersCarryTheNumbersOfEveryDiagnosisPixel) {
  const Scene scene = ramp_scene();
  const std::vector<ImageWithStep> images = trapezoid_images(scene);
  const std::vector<Candidate> report = diagnose(scene, *scene.camera, pointers(images), 0, {});
  const long all_pixels = static_cast<long>(diagnosis_pixels(40, 40).size());
  const long ranking = static_cast<long>(ranking_pixels(40, 40).size());
  ASSERT_EQ(all_pixels, 1600);
  ASSERT_LT(ranking, all_pixels);
  ASSERT_GE(report.size(), kMinLeaders + 1);
  EXPECT_EQ(report.front().placement, "inviwo");
  EXPECT_EQ(report.front().rule, "trapezoid");
  EXPECT_LT(report.front().rms, 1e-15);
  // The leaders first (nearest first), then the rest by their ranking RMS.
  for (std::size_t i = 0; i < report.size(); ++i) {
    EXPECT_EQ(report[i].pixels, i < kMinLeaders ? all_pixels : ranking) << report[i].name;
    if (i > 0 && report[i].pixels == report[i - 1].pixels) {
      EXPECT_GE(report[i].rms, report[i - 1].rms);
    }
  }
  // A leader's RMS is the one over every diagnosis pixel, bit for bit.
  const std::vector<Model> models = distinct_models(scene, verify_toy::kThreeSteps, {});
  const Candidate& second = report[1];
  const Model& m = *std::find_if(models.begin(), models.end(), [&](const Model& x) { return x.label.name == second.name; });
  const std::vector<long> pixels = diagnosis_pixels(40, 40);
  double sum_sq = 0, max = 0;
  long count = 0;
  const auto sorted = pointers(images);
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    const std::vector<double> cast = cast_pixels(scene, *scene.camera, m.per_step[k], pixels);
    for (std::size_t j = 0; j < pixels.size(); ++j) {
      const double d = sorted[k]->image.pixels[pixels[j]] - cast[j];
      sum_sq += d * d, max = std::max(max, std::abs(d)), ++count;
    }
  }
  EXPECT_EQ(second.rms, std::sqrt(sum_sq / count));
  EXPECT_EQ(second.max, max);
}

TEST(DiagnosisCoarseToFine, TheReportDoesNotDependOnTheThreadCount) {
  const Scene scene = ramp_scene();
  const std::vector<ImageWithStep> images = trapezoid_images(scene);
  const auto run = [&](int threads) {
    const ThreadLimit limit(threads);
    return diagnose(scene, *scene.camera, pointers(images), 0, {});
  };
  const std::vector<Candidate> one = run(1), many = run(0);
  ASSERT_EQ(one.size(), many.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].name, many[i].name);
    EXPECT_EQ(one[i].rms, many[i].rms) << one[i].name;
    EXPECT_EQ(one[i].max, many[i].max) << one[i].name;
  }
}

// The estimate is the distinct models' samples on the ranking pixels plus the dearest
// kMinLeaders' on the diagnosis pixels, each from camera_work; halving every step doubles it.
TEST(DiagnosisCoarseToFine, TheWorkEstimateCountsWhatIsCast) {
  const Scene scene = ramp_scene();
  const Camera& camera = *scene.camera;
  const double pixels = 1600, coarse = static_cast<double>(ranking_pixels(40, 40).size());
  std::vector<double> per_model;
  for (const Model& m : distinct_models(scene, verify_toy::kThreeSteps, {})) {
    double samples = 0;
    for (const DiscreteConfig& c : m.per_step) samples += camera_work(scene, camera, 0, &c) / pixels;
    per_model.push_back(samples);
  }
  std::sort(per_model.rbegin(), per_model.rend());
  double expected = 0;
  for (std::size_t m = 0; m < per_model.size(); ++m) expected += per_model[m] * (coarse + (m < kMinLeaders ? pixels : 0));
  const double work = diagnosis_work(scene, camera, verify_toy::kThreeSteps, {});
  EXPECT_DOUBLE_EQ(work, expected);
  std::vector<double> half;
  for (double h : verify_toy::kThreeSteps) half.push_back(h / 2);
  const double finer = diagnosis_work(scene, camera, half, {});
  EXPECT_GT(finer, 1.8 * work);
  EXPECT_LT(finer, 2.2 * work);
}

}  // namespace
}  // namespace vrv
