#include "studies/engine/memory_budget.h"

#include <string>

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "lib/study_file.h"
#include "studies/engine/study_driver.h"

namespace vrv {
namespace {

toml::table parsed(const std::string& text) { return toml::parse(text); }

// A [field] table counts by its kind, wherever the file holds it (cases, lists of them); a key named
// resolution elsewhere is not a grid, and neither an analytic field nor a volume holds nodes the
// table can tell (a volume's reader checks its header against the budget itself).
TEST(StudyMemory, CountsEachFieldTableByItsKind) {
  const toml::table doc = parsed(R"(
kind = "hard_cases"
[[case]]
[case.scene.field]
kind = "grid"
resolution = [10, 20, 30]
[case.scene.field.source]
kind = "marschner_lobb"
[[case]]
[case.scene.field]
kind = "grid"
resolution = [40, 4, 4]
[[case]]
[case.scene.field]
kind = "volume"
file = "ct.nrrd"
[[case]]
[case.scene.field]
kind = "linear_ramp"
[export]
resolution = [1000, 1000, 1000]
)");
  const StudyMemory m = estimate_study_memory(doc);
  EXPECT_EQ(m.grids, 2);
  EXPECT_EQ(m.bytes, (10 * 20 * 30 + 40 * 4 * 4) * 8.0);
  EXPECT_EQ(m.largest, (NodeCounts{10, 20, 30}));
}

// A malformed grid is the reader's to report: the estimate neither counts it nor fails.
TEST(StudyMemory, LeavesAMalformedGridToTheReader) {
  const toml::table doc = parsed(R"(
[scene.field]
kind = "grid"
resolution = [10, -2, 3]
)");
  EXPECT_EQ(estimate_study_memory(doc).grids, 0);
}

// The grids a study kind builds of its own are its declaration's: the shading study's refinement
// grids and image grid were invisible to the estimate when it looked for keys named resolution.
TEST(StudyMemory, CountsTheGridsAStudyKindDeclares) {
  const StudyGrids shading = find_study_grids("shading");
  ASSERT_NE(shading, nullptr);
  const toml::table doc = parsed("kind = \"shading\"\ngrids = [17, 65, 33]\nimage_grid = 129\n");
  const StudyMemory m = estimate_study_memory(doc, shading);
  EXPECT_EQ(m.grids, 2);
  EXPECT_EQ(m.bytes, (65.0 * 65 * 65 + 129.0 * 129 * 129) * 8);
  EXPECT_EQ(m.largest, (NodeCounts{129, 129, 129}));
  // Without image_grid the study images its default grid (33^3).
  EXPECT_EQ(estimate_study_memory(parsed("grids = [17, 65]\n"), shading).bytes, (65.0 * 65 * 65 + 33.0 * 33 * 33) * 8);

  // convergence: one of its [grid_refinement] lists is built, one grid at a time.
  const StudyGrids convergence = find_study_grids("convergence");
  ASSERT_NE(convergence, nullptr);
  const StudyMemory c = estimate_study_memory(
      parsed("[grid_refinement]\nresolutions = [17, 129, 65]\nquick_resolutions = [9, 17, 33]\n"), convergence);
  EXPECT_EQ(c.grids, 1);
  EXPECT_EQ(c.largest, (NodeCounts{129, 129, 129}));

  // opacity_correction: the render's grid of [render] resolution.
  const StudyGrids opacity = find_study_grids("opacity_correction");
  ASSERT_NE(opacity, nullptr);
  EXPECT_EQ(estimate_study_memory(parsed("[render]\nresolution = [64, 32, 16]\n"), opacity).bytes, 64.0 * 32 * 16 * 8);

  EXPECT_EQ(find_study_grids("hard_cases"), nullptr);  // its grids are its scenes' [field] tables
}

}  // namespace
}  // namespace vrv
