#include "lib/bounds_file.h"

#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace vrv {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_bounds(text, "b.toml");
  } catch (const BoundsFileError& e) {
    return e.what();
  }
  return "no error";
}

TEST(BoundsFile, ReadsDefaultsCasesAndOverrides) {
  const BoundsFile f = parse_bounds(R"(
description = "d"
[defaults]
threshold = 1e-4
rms = { warn = 1e-4, fail = 1e-3, hard_fail = 1e-2 }
min_order = { warn = 1.9, fail = 1.75 }
max_nan = { fail = 0 }
[[case]]
name = "a"
steps = [0.2, 0.1]
render = { method = "alpha", strategy = "inviwo", opacity_unit = "distance", color = "premultiplied", table_size = 256, table_lookup = "uncentred" }
width = 16
rms = { fail = 5e-3 }
at = "all"
[[case]]
name = "b"
study = "convergence"
)", "dir/b.toml");
  ASSERT_EQ(f.cases.size(), 2u);
  EXPECT_DOUBLE_EQ(*f.defaults.limits.at(Bound::rms).warn, 1e-4);
  const GateCase& a = f.cases[0];
  EXPECT_FALSE(a.bounds.limits.at(Bound::rms).warn);  // the case's table replaces the default's
  EXPECT_DOUBLE_EQ(*a.bounds.limits.at(Bound::rms).fail, 5e-3);
  EXPECT_DOUBLE_EQ(*a.bounds.limits.at(Bound::min_order).fail, 1.75);  // inherited
  EXPECT_DOUBLE_EQ(a.bounds.threshold, 1e-4);
  EXPECT_TRUE(a.bounds.all_images);
  EXPECT_EQ(a.render->options.strategy, "inviwo");
  // The opacity/colour conventions of `vrv render` (--opacity-unit, --color, --table-*).
  EXPECT_EQ(a.render->options.opacity_unit, "distance");
  EXPECT_EQ(a.render->options.color, "premultiplied");
  EXPECT_EQ(a.render->options.table_size, 256);
  EXPECT_EQ(a.render->options.table_lookup, "uncentred");
  EXPECT_EQ(*a.width, 16);
  EXPECT_EQ(f.cases[1].study, "convergence");
}

TEST(BoundsFile, ImagesCaseMayLeaveStepsToProvenance) {
  // No steps: vrv gate reads each image's vrv:step; with steps, one per image as before.
  const BoundsFile f = parse_bounds("[[case]]\nname = \"x\"\nimages = [\"a.exr\", \"b.exr\"]\n", "dir/b.toml");
  ASSERT_EQ(f.cases.size(), 1u);
  EXPECT_TRUE(f.cases[0].steps.empty());
  EXPECT_EQ(f.cases[0].images.size(), 2u);
  EXPECT_EQ(f.cases[0].images[1], std::filesystem::path("dir/b.exr"));
  // Paths as a reader writes them: ./b.toml with ../img/a.exr is ../img/a.exr, not ./../img/a.exr.
  const BoundsFile g = parse_bounds("[[case]]\nname = \"x\"\nimages = [\"../img/a.exr\"]\nscene = \"./s.toml\"\n", "./b.toml");
  EXPECT_EQ(g.cases[0].images[0], std::filesystem::path("../img/a.exr"));
  EXPECT_EQ(g.cases[0].scene, std::filesystem::path("s.toml"));
}

// A case's name is its folder under --out: "/abs/dir" wrote into /abs/dir and "../x" beside --out
// (issue 22); only a plain file-name component is taken.
TEST(BoundsFile, CaseNamesArePlainFileNames) {
  const auto named = [](const std::string& name) { return "[[case]]\nname = \"" + name + "\"\nstudy = \"s\"\n"; };
  EXPECT_EQ(error_of(named("/abs/dir")), "b.toml: case[0].name: '/abs/dir' is not a plain file name: no '/', '\\' or "
                                         "control characters (it names the folder OUT/NAME)");
  EXPECT_NE(error_of(named("../x")).find("case[0].name: '../x' begins with '.'"), std::string::npos);
  EXPECT_NE(error_of(named("..")).find("begins with '.'"), std::string::npos);
  EXPECT_NE(error_of(named("a\\tb")).find("not a plain file name"), std::string::npos);
  EXPECT_NE(error_of(named("")).find("case[0].name: empty"), std::string::npos);
  EXPECT_NE(error_of(named(std::string(101, 'n'))).find("101 bytes, more than 100"), std::string::npos);
  EXPECT_EQ(error_of(named("alpha step 0.1")), "no error");
}

// A render case takes `vrv render`'s options as keys (lib/discrete_options.h), read as study files
// read them, but not the step (the case's steps), the rate or the work limit.
TEST(BoundsFile, RenderCaseTakesTheDiscreteOptions) {
  const BoundsFile f = parse_bounds(
      "[[case]]\nname = \"x\"\nsteps = [0.1, 0.05]\n"
      "render = { termination = 0.99, classification = \"pre\", centred_oversamples = true, oversample = 2 }\n",
      "b.toml");
  const DiscreteOptions& o = f.cases.at(0).render->options;
  EXPECT_EQ(o.method, "alpha");  // the defaults of a render case
  EXPECT_EQ(o.strategy, "step");
  EXPECT_EQ(o.termination, 0.99);
  EXPECT_EQ(o.classification, "pre");
  EXPECT_TRUE(o.centred_oversamples);
  EXPECT_EQ(o.oversample, 2);
  EXPECT_TRUE(o.was_given(Option::termination));
  EXPECT_FALSE(o.was_given(Option::skip));
  for (const char* key : {"step", "rate", "max_work"}) {
    const std::string text = fmt::format("[[case]]\nname = \"x\"\nsteps = [0.1]\nrender = {{ {} = 1 }}\n", key);
    EXPECT_EQ(error_of(text).rfind(fmt::format("b.toml: case[0].render.{}: unknown key", key), 0), 0u) << error_of(text);
  }
  EXPECT_EQ(error_of("[[case]]\nname = \"x\"\nsteps = [0.1]\nrender = { skip = \"low\" }\n"),
            "b.toml: case[0].render.skip: expected a number");
}

TEST(BoundsFile, ErrorsNameFileAndKey) {
  EXPECT_EQ(error_of("[defaults]\nrms = { fial = 1 }\n").rfind("b.toml: defaults.rms.fial: unknown key", 0), 0u) << error_of("[defaults]\nrms = { fial = 1 }\n");
  EXPECT_NE(error_of("[defaults]\nrms = { warn = 1, fail = 0.5 }\n").find("ordered"), std::string::npos);
  EXPECT_NE(error_of("[defaults]\nmin_order = { warn = 1, fail = 1.5 }\n").find("ordered"), std::string::npos);
  EXPECT_NE(error_of("[defaults]\nrms = {}\n").find("at least one"), std::string::npos);
  EXPECT_NE(error_of("[[case]]\nname = \"x\"\nsteps = [0.1]\n").find("exactly one of"), std::string::npos);
  EXPECT_NE(error_of("[[case]]\nname = \"x\"\nsteps = [0.1, 0.2]\nimages = [\"a.exr\"]\n").find("1 images for 2 steps"),
            std::string::npos);
  EXPECT_NE(error_of("[[case]]\nname = \"x\"\nrender = { method = \"alpha\" }\n").find("b.toml: case[0].steps"),
            std::string::npos);
  EXPECT_NE(error_of("[[case]]\nname = \"x\"\nimages = []\n").find("case[0].images: empty"), std::string::npos);
  EXPECT_NE(error_of("[[case]]\nname = \"x\"\nstudy = \"s\"\n[[case]]\nname = \"x\"\nstudy = \"t\"\n").find("repeats"),
            std::string::npos);
  EXPECT_NE(error_of("colour = 1\n").find("colour"), std::string::npos);
  EXPECT_NE(error_of("[defaults]\nrms = { fail = nan }\n").find("defaults.rms.fail"), std::string::npos);
}

}  // namespace
}  // namespace vrv
