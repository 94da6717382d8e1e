#include "lib/util/enum_names.h"

#include <gtest/gtest.h>

namespace vrv {
namespace {

enum class Fruit { apple, pear, plum };

// The check every NameTable passes beside its definition (static_assert) fails for the tables a
// slip would make: a row left out (the default row: apple, no name), a name or a value twice.
TEST(EnumNames, NamesCompleteRefusesARowLeftOutOrRepeated) {
  constexpr NameTable<Fruit, 3> whole{{{Fruit::apple, "apple"}, {Fruit::pear, "pear"}, {Fruit::plum, "plum"}}};
  constexpr NameTable<Fruit, 3> short_list{{{Fruit::pear, "pear"}, {Fruit::plum, "plum"}}};
  constexpr NameTable<Fruit, 3> name_twice{{{Fruit::apple, "apple"}, {Fruit::pear, "pear"}, {Fruit::plum, "pear"}}};
  constexpr NameTable<Fruit, 3> value_twice{{{Fruit::apple, "apple"}, {Fruit::pear, "pear"}, {Fruit::pear, "plum"}}};
  static_assert(names_complete(whole));
  EXPECT_FALSE(names_complete(short_list));
  EXPECT_FALSE(names_complete(name_twice));
  EXPECT_FALSE(names_complete(value_twice));
  EXPECT_EQ(parse_name(whole, "plum"), Fruit::plum);
  EXPECT_EQ(name_of(whole, Fruit::pear), "pear");
  EXPECT_EQ(parse_name(whole, "fig"), std::nullopt);
}

}  // namespace
}  // namespace vrv
