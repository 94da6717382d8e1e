// The options' one vocabulary: each option has a key and a flag derived from it, and an
// OptionError names the option, and the options its reason mentions, as each front end spells them.
#include "lib/option_error.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

#include "lib/discrete_raycast.h"
#include "lib/sampling.h"

namespace vrv {
namespace {

TEST(OptionError, EveryOptionHasAKeyAndAFlagDerivedFromIt) {
  std::set<std::string> keys;
  for (int i = 0; i <= static_cast<int>(Option::max_work); ++i) {
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
  const OptionError plain(Option::compositing, "unknown value '{' (front_to_back or back_to_front)");
  EXPECT_EQ(std::string(plain.what()), "--compositing: unknown value '{' (front_to_back or back_to_front)");
  const OptionError mentions(Option::method, "unknown value '" + literal("{0}}") + "' for {0} mip", {Option::mode});
  EXPECT_EQ(std::string(mentions.what()), "--method: unknown value '{0}}' for --mode mip");
  EXPECT_EQ(mentions.message(Spelling::key), "method: unknown value '{0}}' for mode mip");
}

TEST(OptionError, FlagsMapBackToTheirOption) {
  for (int i = 0; i <= static_cast<int>(Option::max_work); ++i) {
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

}  // namespace
}  // namespace vrv
