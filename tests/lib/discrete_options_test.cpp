// The one vocabulary of a discrete raycast's options (lib/discrete_options): declared once, read
// alike by every adapter (here the study file's, read_study_method, against DiscreteOptions filled
// directly as the command line and Python fill it), each failure named as its user wrote it.
#include <algorithm>
#include <map>
#include <regex>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "lib/discrete_options.h"
#include "lib/gradient_scheme.h"
#include "lib/opacity_correction.h"
#include "lib/sampling.h"
#include "lib/segment_rule.h"
#include "lib/transfer_table.h"
#include "lib/scene_file.h"
#include "lib/study_file.h"

namespace vrv {
namespace discrete_options_test {
namespace {

// The configuration a study file's method gives, or its one-line error.
struct StudyRead {
  std::optional<StudyMethodSpec> spec;
  std::string error;
};

StudyRead read_method(const std::string& lines, const Scene& scene = default_scene()) {
  const StudyReader r("s.toml");
  const toml::table doc = parse_study_toml("[m]\n" + lines, "s.toml");
  try {
    return {read_study_method(r, *doc["m"].as_table(), "m", scene), ""};
  } catch (const StudyFileError& e) {
    return {std::nullopt, e.what()};
  }
}

TEST(DiscreteOptions, EveryOptionIsDeclaredOnceWithHelp) {
  std::set<Option> seen;
  for (const DiscreteOptionField& f : discrete_option_fields()) {
    EXPECT_TRUE(seen.insert(f.option).second) << option_name(f.option, Spelling::key);
    EXPECT_FALSE(f.help.empty()) << option_name(f.option, Spelling::key);
    EXPECT_EQ(discrete_option_field(f.option), &f);
  }
  EXPECT_EQ(discrete_option_field(Option::mode), nullptr);  // the projections' own option
  // Every Option but mode is a discrete raycast's.
  EXPECT_EQ(seen.size() + 1, static_cast<std::size_t>(Option::shade_at) + 1);
}

// Each option's help offers every choice its parser takes (the help is prose, the choices a table:
// a new strategy or rule must reach both).
TEST(DiscreteOptions, HelpNamesEveryChoice) {
  const std::map<Option, std::string> choices = {
      {Option::method, segment_rule_list()},         {Option::strategy, strategy_list()},
      {Option::correction, correction_list()},       {Option::compositing, compositing_list()},
      {Option::classification, classification_list()}, {Option::precision, precision_list()},
      {Option::opacity_unit, opacity_unit_list()},   {Option::color, color_convention_list()},
      {Option::table_lookup, table_lookup_list()},   {Option::gradient, gradient_scheme_list()},
      {Option::shade_at, shade_at_list()}};
  for (const auto& [option, list] : choices) {
    const std::string help(discrete_option_field(option)->help);
    for (std::size_t start = 0; start < list.size();) {
      const std::size_t end = std::min(list.find(", ", start), list.size());
      const std::string name = list.substr(start, end - start);
      EXPECT_TRUE(std::regex_search(help, std::regex("\\b" + name + "\\b"))) << option_name(option, Spelling::key) << " lacks " << name;
      start = end + 2;
    }
  }
}

// A study file names every option the command line has (issue 19: it lacked termination, skip,
// compositing and classification), and reads it to the configuration the command line's
// DiscreteOptions gives.
TEST(DiscreteOptions, StudyFileReadsTheCommandLinesConfiguration) {
  const Scene scene = default_scene();
  DiscreteOptions opt;
  opt.method = "alpha";
  opt.strategy = "vtk";
  opt.step = 0.02;
  opt.oversample = 3;
  opt.centred_oversamples = true;
  opt.correction = "lee_newman";
  opt.termination = 0.95;
  opt.skip = 0.001;
  opt.precision = "float";
  const DiscreteConfig cli = *discrete_config(opt, scene);
  const StudyRead study = read_method(
      "method = 'alpha'\nstrategy = 'vtk'\nstep = 0.02\noversample = 3\ncentred_oversamples = true\n"
      "correction = 'lee_newman'\ntermination = 0.95\nskip = 0.001\nprecision = 'float'\n");
  ASSERT_TRUE(study.spec) << study.error;
  const DiscreteConfig& c = study.spec->config;
  EXPECT_EQ(c.rule, cli.rule);
  EXPECT_EQ(c.sampling.strategy, cli.sampling.strategy);
  EXPECT_EQ(c.sampling.step, cli.sampling.step);
  EXPECT_EQ(c.sampling.rate, cli.sampling.rate);
  EXPECT_EQ(c.sampling.dims, cli.sampling.dims);
  EXPECT_EQ(c.oversample, cli.oversample);
  EXPECT_EQ(c.centred_oversamples, cli.centred_oversamples);
  EXPECT_EQ(c.correction, cli.correction);
  EXPECT_EQ(c.termination, cli.termination);
  EXPECT_EQ(c.skip_below, cli.skip_below);
  EXPECT_EQ(c.precision, cli.precision);
  EXPECT_EQ(study.spec->label, "alpha vtk h=0.02 N=3 centred lee_newman termination=0.95 skip<0.001 float");

  const StudyRead back = read_method("method = 'riemann'\nstrategy = 'step'\nstep = 0.1\ncompositing = 'back_to_front'\n");
  ASSERT_TRUE(back.spec) << back.error;
  EXPECT_EQ(back.spec->config.compositing, Compositing::back_to_front);
  EXPECT_EQ(back.spec->label, "riemann step h=0.1 back_to_front double");
  EXPECT_EQ(method_json(*back.spec).at("compositing"), "back_to_front");
}

// Defaults are not written into labels or meta.json: files that never name an option keep theirs.
TEST(DiscreteOptions, DefaultsLeaveLabelsAsTheyWere) {
  const StudyRead plain = read_method("method = 'trapezoid'\nstrategy = 'step'\nstep = 0.05\n");
  ASSERT_TRUE(plain.spec) << plain.error;
  EXPECT_EQ(plain.spec->label, "trapezoid step h=0.05 double");
  const auto j = method_json(*plain.spec);
  for (const char* key : {"termination", "skip", "compositing", "classification"}) EXPECT_FALSE(j.contains(key)) << key;
}

// The command line's checks, each named by the key the file uses.
TEST(DiscreteOptions, StudyFileErrorsNameTheKey) {
  const std::string step = "method = 'alpha'\nstrategy = 'step'\nstep = 0.1\n";
  EXPECT_EQ(read_method(step + "termination = 1.5\n").error, "s.toml: m.termination: must be in (0, 1]");
  EXPECT_EQ(read_method(step + "skip = 1\n").error, "s.toml: m.skip: must be in [0, 1)");
  EXPECT_EQ(read_method(step + "termination = 0.9\ncompositing = 'back_to_front'\n").error,
            "s.toml: m.termination: early termination needs front-to-back compositing");
  EXPECT_EQ(read_method(step + "compositing = 'sideways'\n").error,
            "s.toml: m.compositing: unknown value 'sideways' (one of front_to_back, back_to_front)");
  EXPECT_EQ(read_method(step + "classification = 'pre'\n").error.rfind("s.toml: m.classification: ", 0), 0u)
      << "pre-classification needs a grid; the default scene is analytic";
  EXPECT_EQ(read_method(step + "gradient = 'nodes'\n").error,
            "s.toml: m.gradient: applies to a shaded scene only (one with a [shading] table)");
  EXPECT_EQ(read_method(step + "termination = 'high'\n").error, "s.toml: m.termination: expected a number");
  EXPECT_EQ(read_method("method = 'reference'\ntol = 1e-10\nskip = 0.1\n").error,
            "s.toml: m.skip: not used by the reference method");
  EXPECT_EQ(read_method(step + "max_work = 10\n").error.rfind("s.toml: m.max_work: unknown key", 0), 0u);
  EXPECT_EQ(read_method("method = 'alpha'\nstrategy = 'entry'\nrate = 0\n").error,
            "s.toml: m.rate: must be a positive finite number, got 0");
  // Accepted, it would change nothing: centred oversamples without oversampling.
  EXPECT_EQ(read_method(step + "centred_oversamples = true\n").error,
            "s.toml: m.centred_oversamples: needs oversample N > 1 (one sample a step is the unit sample itself)");
  EXPECT_EQ(read_method(step + "centred_oversamples = true\noversample = 2\n").error, "");
  // Premultiplied colour acts on an emission/extinction scene too (with an opacity correction).
  EXPECT_EQ(read_method(step + "color = 'premultiplied'\ncorrection = 'lacroute'\n").error, "");
}

// Without a method every other option is refused, first in the declared order.
TEST(DiscreteOptions, OptionsWithoutAMethodAreRefused) {
  DiscreteOptions opt;
  EXPECT_FALSE(discrete_config(opt, default_scene()));
  opt.give(Option::skip, "0.1");
  opt.give(Option::rate, "2");
  try {
    discrete_config(opt, default_scene());
    FAIL();
  } catch (const OptionError& e) {
    EXPECT_EQ(e.option(), Option::rate);
    EXPECT_EQ(e.message(Spelling::key), "rate: applies to a discrete raycast only; add method (the reference ignores it)");
  }
}

// The work refusal quotes the rate, step and oversample as the user gave them.
TEST(DiscreteOptions, WorkRefusalQuotesTheGivenText) {
  DiscreteOptions opt;
  opt.give(Option::oversample, "4");
  opt.give(Option::step, "1e-9");
  try {
    refuse_work(opt, true, 2e9, 1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--step 1e-9, --oversample 4: about 2e+09 samples on 1 ray, above the work limit", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace discrete_options_test
}  // namespace vrv
