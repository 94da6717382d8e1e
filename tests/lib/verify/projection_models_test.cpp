// vrv verify for projection images (lib/verify/projection_models.h): an independent renderer (its
// own sample loop and rules, not vrv's discrete projection) renders MIP and X-ray images of the
// toy scene at four steps; they pass at the mode's expected order, and planted faults do not.
#include "lib/verify/projection_models.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "lib/projection/projection_reference.h"
#include "lib/verify/reference_cache.h"
#include "lib/verify/verify_report_html.h"
#include "tests/lib/verify/verify_toy.h"

namespace vrv {
namespace {

using verify_toy::images_in_memory;
using verify_toy::kScene;

enum class Planted { none, first_sample_dropped, step_not_multiplied };

// The independent renderer: the clipped ray cut into n = ceil(L / step) equal steps, the field at
// the n + 1 nodes (entry and exit included); MIP the largest node, X-ray the trapezoid rule.
std::vector<double> project(const Scene& scene, double step, bool mip, Planted planted) {
  const Camera& cam = *scene.camera;
  std::vector<double> out(static_cast<std::size_t>(cam.width) * cam.height, 0.0);
  visit_field(scene, [&](const auto& field) {
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const Ray ray = cam.ray(x, y);
        const auto iv = clip(ray, scene.box);
        if (!iv || !(iv->t1 > iv->t0)) continue;
        const long n = std::max(1L, static_cast<long>(std::ceil((iv->t1 - iv->t0) / step)));
        const double h = (iv->t1 - iv->t0) / static_cast<double>(n);
        double best = -1e300, sum = 0;
        for (long k = planted == Planted::first_sample_dropped ? 1 : 0; k <= n; ++k) {
          const double v = field.value(ray.at(iv->t0 + static_cast<double>(k) * h));
          best = std::max(best, v);
          const double w = (k == 0 || k == n) ? 0.5 : 1.0;
          sum += w * v * (planted == Planted::step_not_multiplied ? 1.0 : h);
        }
        out[static_cast<std::size_t>(y) * cam.width + x] = mip ? best : sum;
      }
  });
  return out;
}

// Marschner-Lobb's rings (f_M = 6) are resolved from about h = 0.025 on: a sampled MIP is in its
// asymptotic O(h^2) range there (at h = 0.1 it still skips whole rings).
const std::vector<double> kMipSteps{0.025, 0.0125, 0.00625, 0.003125};

std::vector<ImageWithStep> images(const Scene& scene, bool mip, Planted planted) {
  return images_in_memory(scene, [&](double h) { return project(scene, h, mip, planted); }, "projection",
                          mip ? kMipSteps : verify_toy::kSteps);
}

VerifyOptions mode_options(ProjectionMode mode) {
  VerifyOptions o;
  o.mode = mode;
  return o;
}

class ProjectionVerify : public ::testing::Test {
 protected:
  Scene scene = parse_scene(kScene, "toy.toml");
};

TEST_F(ProjectionVerify, IndependentMipPassesAtOrderTwoWithTheProjectionDiagnosis) {
  const VerifyReport r = verify_images(scene, images(scene, true, Planted::none), mode_options(ProjectionMode::mip));
  EXPECT_TRUE(r.pass) << (r.failures.empty() ? "" : r.failures.front());
  EXPECT_EQ(r.verdict.verdict, Verdict::converges);
  ASSERT_TRUE(r.expected_order);
  EXPECT_EQ(*r.expected_order, 2);  // the mode's, none given
  EXPECT_GE(r.orders.front().fit.order, 1.75);
  ASSERT_TRUE(r.mode);
  EXPECT_EQ(*r.mode, "mip");
  ASSERT_EQ(r.notes.size(), 1u);  // the EA catalogue and conventions are said to be skipped
  EXPECT_TRUE(r.faults.empty());
  EXPECT_TRUE(r.conventions.empty());
  EXPECT_TRUE(r.fault_fits.empty());
  ASSERT_FALSE(r.diagnosis.empty());
  EXPECT_EQ(r.diagnosis.size(), 5u);  // five placements x max
  EXPECT_EQ(r.diagnosis.front().rule, "max");
  EXPECT_NE(r.diagnosis.front().name.find("mip"), std::string::npos);
  EXPECT_LE(r.diagnosis.front().rms, r.diagnosis.back().rms);
}

// The page says the mode and what was not run; an emission-absorption page says neither.
TEST_F(ProjectionVerify, ReportPageNamesTheModeAndWhatWasNotRun) {
  VerifyOptions o = mode_options(ProjectionMode::mip);
  o.diagnose = false;
  const VerifyReport r = verify_images(scene, images(scene, true, Planted::none), o);
  const std::string page = verify_report_html(r, {});
  EXPECT_NE(page.find("mode <b>mip</b>"), std::string::npos);
  EXPECT_NE(page.find(html_escape(kProjectionSkipNote)), std::string::npos);
  VerifyReport ea = r;
  ea.mode.reset();
  ea.notes.clear();
  EXPECT_EQ(verify_report_html(ea, {}).find("id=\"mode\""), std::string::npos);
}

TEST_F(ProjectionVerify, MipMissingItsEntrySampleIsFlagged) {
  const VerifyReport r =
      verify_images(scene, images(scene, true, Planted::first_sample_dropped), mode_options(ProjectionMode::mip));
  EXPECT_FALSE(r.pass);
  EXPECT_NE(r.verdict.verdict, Verdict::converges);
  EXPECT_LT(r.orders.front().fit.order, 1.5);
}

TEST_F(ProjectionVerify, IndependentXrayPassesAndItsDiagnosisHasEveryRule) {
  const VerifyReport r = verify_images(scene, images(scene, false, Planted::none), mode_options(ProjectionMode::xray));
  EXPECT_TRUE(r.pass) << (r.failures.empty() ? "" : r.failures.front());
  EXPECT_EQ(r.verdict.verdict, Verdict::converges);
  EXPECT_GE(r.orders.front().fit.order, 1.75);
  EXPECT_EQ(r.diagnosis.size(), 15u);  // five placements x riemann, trapezoid, simpson
  EXPECT_EQ(r.reference.missed, 0);
}

TEST_F(ProjectionVerify, XrayNotMultipliedByTheStepIsFlagged) {
  const VerifyReport r =
      verify_images(scene, images(scene, false, Planted::step_not_multiplied), mode_options(ProjectionMode::xray));
  EXPECT_FALSE(r.pass);
  EXPECT_NE(r.verdict.verdict, Verdict::converges);
}

TEST_F(ProjectionVerify, ReferenceIsTheProjectionReferencePerPixel) {
  VerifyOptions o = mode_options(ProjectionMode::xray);
  const Camera cam = verify_camera(scene, o, 32, 32);
  const ReferenceImage ref = reference_image(scene, cam, o);
  for (int i : {0, 17 * 32 + 15, 32 * 32 - 1}) {
    const ProjectionResult p = projection_reference(scene, cam.ray(i % 32, i / 32), ProjectionMode::xray, {o.reference_tol});
    EXPECT_EQ(ref.pixels[i], p.value);
    EXPECT_EQ(ref.optical_depth[i], 0.0);
  }
}

// The cache key: one per mode; emission-absorption's as before (the scene text, its files).
TEST_F(ProjectionVerify, CacheKeysDifferPerModeAndEmissionAbsorptionKeepsItsKey) {
  const std::filesystem::path dir = verify_toy::scratch() / "projection_cache";
  std::filesystem::remove_all(dir);
  VerifyOptions o;
  o.cache_dir = dir;
  o.scene_text = kScene;
  const Camera cam = verify_camera(scene, o, 8, 8);
  const ReferenceImage ea = reference_image(scene, cam, o);
  EXPECT_EQ(std::filesystem::path(ea.cache_file).filename(),
            reference_cache_name(reference_cache_key(std::string(kScene) + scene.field_files, cam, o.reference_tol)));
  o.mode = ProjectionMode::mip;
  const ReferenceImage mip = reference_image(scene, cam, o);
  EXPECT_FALSE(mip.from_cache);
  o.mode = ProjectionMode::xray;
  const ReferenceImage xray = reference_image(scene, cam, o);
  EXPECT_FALSE(xray.from_cache);
  EXPECT_NE(mip.cache_file, xray.cache_file);
  EXPECT_NE(mip.cache_file, ea.cache_file);
  EXPECT_NE(mip.pixels, xray.pixels);
  const ReferenceImage again = reference_image(scene, cam, o);
  EXPECT_TRUE(again.from_cache);
  EXPECT_EQ(again.pixels, xray.pixels);
}

// The estimate before a projection's diagnosis: its models' samples, not the EA catalogue's.
TEST_F(ProjectionVerify, DiagnosisWorkIsTheProjectionModelsSamples) {
  const std::vector<double> steps{0.1, 0.05};
  VerifyOptions o = mode_options(ProjectionMode::mip);
  const Camera cam = verify_camera(scene, o, 32, 32);
  const double mip = verification_work(scene, o, 32, 32, steps).diagnosis;
  o.mode = ProjectionMode::xray;
  const double xray = verification_work(scene, o, 32, 32, steps).diagnosis;
  o.mode.reset();
  const double ea = verification_work(scene, o, 32, 32, steps).diagnosis;
  // 32 x 32 pixels, rays of at most the box's diagonal: at most 35 samples a ray at h = 0.1 and 70 at 0.05.
  EXPECT_GT(mip, 0);
  EXPECT_LE(mip, 5 * 1024 * (35 + 70) * 1.05);
  EXPECT_DOUBLE_EQ(xray, mip * (1 + 1 + 2));  // riemann, trapezoid, simpson (twice)
  EXPECT_LT(mip, ea);
  EXPECT_DOUBLE_EQ(mip, projection_diagnosis_work(scene, cam, ProjectionMode::mip, steps));
}

TEST(ProjectionModels, ExpectedOrderIsTwoExceptAClassifiedMipPeakingAtACorner) {
  const TransferFunction rising = TransferFunction::emission_extinction(PiecewiseLinear({{0, 0}, {1, 1}}),
                                                                        PiecewiseLinear({{0, 0}, {1, 0.5}}));
  // The projections study's transfer function: tau peaks at the corner v = 0.4.
  const TransferFunction peaked = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {1, 1}}), PiecewiseLinear({{0, 0}, {0.4, 1}, {1, 0.5}}));
  // A plateau at the top is no corner peak: the maximum is reached over an interval.
  const TransferFunction plateau = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {1, 1}}), PiecewiseLinear({{0, 0}, {0.4, 1}, {0.6, 1}, {1, 0.5}}));
  for (ProjectionMode m : {ProjectionMode::xray, ProjectionMode::xray_classified, ProjectionMode::mip,
                           ProjectionMode::mip_classified}) {
    EXPECT_EQ(expected_projection_order(m, rising), 2) << projection_mode_name(m);
    EXPECT_EQ(expected_projection_order(m, plateau), 2) << projection_mode_name(m);
    EXPECT_EQ(expected_projection_order(m, peaked), m == ProjectionMode::mip_classified ? 1 : 2)
        << projection_mode_name(m);
  }
}

}  // namespace
}  // namespace vrv
