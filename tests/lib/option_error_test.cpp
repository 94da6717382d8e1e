// The options' one vocabulary: each option has a key and a flag derived from it, and an
// OptionError names the option, and the options its reason mentions, as each front end spells them.
#include "lib/option_error.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

#include "lib/discrete_plan.h"
#include "lib/discrete_raycast.h"
#include "lib/reference_integrator.h"
#include "lib/sampling.h"
#include "lib/verify/verify_options.h"
#include "lib/vrv.h"

namespace vrv {
namespace {

TEST(OptionError, EveryOptionHasAKeyAndAFlagDerivedFromIt) {
  std::set<std::string> keys;
  for (int i = 0; i <= static_cast<int>(kLastOption); ++i) {
    const auto o = static_cast<Option>(i);
    const std::string key(option_name(o, Spelling::key)), flag(option_name(o, Spelling::flag));
    EXPECT_NE(key, "unknown");
    EXPECT_TRUE(keys.insert(key).second) << key << " twice";
    std::string expected = "--" + key;
    for (char& c : expected)
      if (c == '_') c = '-';
    EXPECT_EQ(flag, expected);
  }
  EXPECT_EQ(option_name(Option::table_size, Spelling::flag), "--table-size");
  EXPECT_EQ(option_name(Option::table_size, Spelling::key), "table_size");
}

TEST(OptionError, MessagesSpellTheOptionAndWhatItMentionsAsTheUserWrote) {
  const OptionError e(Option::table_lookup, "needs {0} N (a table to read)", {Option::table_size});
  EXPECT_EQ(std::string(e.what()), "--table-lookup: needs --table-size N (a table to read)");
  EXPECT_EQ(e.message(Spelling::flag), e.what());
  EXPECT_EQ(e.message(Spelling::key), "table_lookup: needs table_size N (a table to read)");
  EXPECT_EQ(e.reason(Spelling::key), "needs table_size N (a table to read)");
  EXPECT_EQ(e.option(), Option::table_lookup);
}

// A user's value is shown as typed: with braces in a plain reason, and through literal() in a
// reason that mentions options.
TEST(OptionError, ValuesWithBracesAreShownAsTyped) {
  const OptionError plain(Option::compositing, "unknown value '{' (one of front_to_back, back_to_front)");
  EXPECT_EQ(std::string(plain.what()), "--compositing: unknown value '{' (one of front_to_back, back_to_front)");
  const OptionError mentions(Option::method, "unknown value '" + literal("{0}}") + "' for {0} mip", {Option::mode});
  EXPECT_EQ(std::string(mentions.what()), "--method: unknown value '{0}}' for --mode mip");
  EXPECT_EQ(mentions.message(Spelling::key), "method: unknown value '{0}}' for mode mip");
}

TEST(OptionError, FlagsMapBackToTheirOption) {
  for (int i = 0; i <= static_cast<int>(kLastOption); ++i) {
    const auto o = static_cast<Option>(i);
    EXPECT_EQ(option_from_flag(option_name(o, Spelling::flag)), o);
  }
  EXPECT_FALSE(option_from_flag("--scene"));
  EXPECT_FALSE(option_from_flag("table_size"));  // a key, not a flag
}

// The library's checks throw OptionError naming the option they refuse.
TEST(OptionError, TheLibrarysChecksNameTheOption) {
  DiscreteConfig c;
  c.table_lookup = TableLookup::uncentred;
  try {
    validate(c, false);
    FAIL() << "no error";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.option(), Option::table_lookup);
    EXPECT_EQ(e.message(Spelling::key), "table_lookup: needs table_size N (a table to read)");
  }
  SamplingConfig s;
  s.strategy = Strategy::step;
  s.step = -1;
  const Ray ray = make_ray(Vec3(-3, 0, 0), Vec3(1, 0, 0));
  try {
    plan_samples(s, ray, Interval{2, 4}, Box{});
    FAIL() << "no error";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.option(), Option::step);
    EXPECT_EQ(std::string(e.what()), "--step: must be a positive finite number, got -1");
  }
}

// Beyond the discrete options: the reference's tolerance, an image's size, verify's and plan's
// options, each named as the user wrote it (Python says tol, the command line --tol).
TEST(OptionError, TheReferenceImageVerifyAndPlanChecksNameTheirOption) {
  const auto refused = [](auto&& call, Option option, const std::string& key_message) {
    try {
      call();
      ADD_FAILURE() << key_message << ": no error";
    } catch (const OptionError& e) {
      EXPECT_EQ(e.option(), option) << e.what();
      EXPECT_EQ(e.message(Spelling::key), key_message);
    }
  };
  refused([] { validate(ReferenceOptions{-1}); }, Option::tol, "tol: must be a positive finite number, got -1");
  refused([] { scene_camera(default_scene(), 0, 8); }, Option::width, "width: must be in [1, 16384], got 0");
  refused([] { scene_camera(default_scene(), 8, 20000); }, Option::height, "height: must be in [1, 16384], got 20000");
  VerifyOptions o;
  refused([&] { apply(VerifySettings{1e-10, 0.25, "median", 0, "auto"}, o); }, Option::order_metric,
          "order_metric: 'median' is not one of max, mean, rms, p99");
  refused([&] { apply(VerifySettings{1e-10, 0.25, "rms", 0, "linear"}, o); }, Option::alpha,
          "alpha: 'linear' is not one of auto, premultiplied, straight");
  refused([] { plan_options({1e-3, "p99", "alpha", "step", 1e9}); }, Option::metric,
          "metric: unknown value 'p99' (max or rms)");
  refused([] { plan_options({1e-3, "max", "alpha,simpson", "step", 1e9}); }, Option::rules,
          "rules: unknown rule 'simpson' (riemann, alpha, trapezoid, exact_linear, moreland)");
  refused([] { plan_options({-1, "max", "alpha", "step", 1e9}); }, Option::target,
          "target: must be a positive finite error, got -1");
  // A value is shown as typed, braces and all.
  refused([] { plan_options({1e-3, "{x}", "alpha", "step", 1e9}); }, Option::metric,
          "metric: unknown value '{x}' (max or rms)");
  refused([&] { apply(VerifySettings{1e-10, 0.25, "rms", 0, "{0}"}, o); }, Option::alpha,
          "alpha: '{0}' is not one of auto, premultiplied, straight");
}

}  // namespace
}  // namespace vrv
