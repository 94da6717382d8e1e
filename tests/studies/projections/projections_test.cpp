// The projections study (studies/projections/): its --quick run's orders within their derived
// tolerances and its references within reference_tol; a bad key is refused naming it.
#include "studies/projections/projections.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>

#include "lib/study_file.h"

namespace vrv {
namespace {

ProjectionsStudy parse(const std::string& text, const std::string& name) {
  const StudyReader r(name);
  const toml::table doc = parse_study_toml(text, name);
  return read_projections_study(StudyInput{doc, r, "projections"});
}

TEST(ProjectionsStudy, QuickRunMeetsTheExpectedOrders) {
  const std::filesystem::path file = std::filesystem::path(VRV_SOURCE_DIR) / "studies/projections/projections.toml";
  const ProjectionsStudy study = parse(read_study_text(file), file.string());
  ASSERT_EQ(study.methods.size(), 8u);
  const ProjectionsResult r = run_projections(study, /*quick=*/true);
  EXPECT_EQ(r.rays, study.quick_rays);
  EXPECT_EQ(r.truths.missed, 0);
  std::set<ProjectionMode> modes;
  for (const ProjectionsMethod& m : study.methods) modes.insert(m.config.mode);
  EXPECT_EQ(r.truths.rays, static_cast<long>(modes.size()) * r.rays);  // each mode's, once per ray
  EXPECT_LE(r.truths.largest_estimate, study.reference_tol);
  ASSERT_EQ(r.orders.size(), 8u);
  for (const ProjectionsOrder& o : r.orders)
    EXPECT_TRUE(order_matches(o.fit, o.expected, study.order_tolerance)) << o.method << ": " << o.fit.order;
  for (const StudyCheck& c : projections_checks(study, r)) EXPECT_TRUE(c.pass) << c.name << " " << c.value;
}

// The images: one error map per distinct cast, a sampled MIP never above the exact maximum (by
// more than the reference's estimate), finite errors, and the references within reference_tol.
TEST(ProjectionsStudy, QuickImagesAreConsistent) {
  const std::filesystem::path file = std::filesystem::path(VRV_SOURCE_DIR) / "studies/projections/projections.toml";
  const ProjectionsStudy study = parse(read_study_text(file), file.string());
  const ProjectionsImages im = run_projections_images(study, /*quick=*/true);
  EXPECT_EQ(im.width, study.quick_image_size);
  EXPECT_EQ(im.height, study.quick_image_size);
  ASSERT_EQ(im.references.size(), 3u);  // mip, mip_classified, xray
  ASSERT_EQ(im.error_maps.size(), 6u);  // the three `mip max step` methods cast one image
  for (const ProjectionsErrorMap& m : im.error_maps) {
    ASSERT_EQ(m.error.pixels.size(), static_cast<std::size_t>(im.width) * im.height) << m.method;
    EXPECT_TRUE(std::isfinite(m.rms_error)) << m.method;
    EXPECT_GT(m.max_error, 0) << m.method;  // the coarsest step is not exact anywhere it matters
    if (m.method.rfind("mip", 0) == 0) {
      for (float e : m.error.pixels) ASSERT_LE(e, 1e-6f) << m.method << ": a sample above the maximum";
    }
  }
  for (const StudyCheck& c : images_checks(study, im)) EXPECT_TRUE(c.pass) << c.name << " " << c.value;
}

TEST(ProjectionsStudy, BadMethodIsRefusedNamingTheKey) {
  const std::string text =
      "kind = \"projections\"\nsteps = [0.1, 0.05, 0.025]\n"
      "[scene.volume]\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n"
      "[scene.field]\nkind = \"marschner_lobb\"\n"
      "[scene.transfer]\nemission = [[0, 0], [1, 1]]\nextinction = [[0, 0], [1, 1]]\n"
      "[[method]]\nmode = \"mip\"\nmethod = \"simpson\"\nstrategy = \"step\"\nexpected_order = 2\n";
  try {
    parse(text, "bad.toml");
    FAIL() << "accepted";
  } catch (const StudyFileError& e) {
    EXPECT_NE(std::string(e.what()).find("method[0].method"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vrv
