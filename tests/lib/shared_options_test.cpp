#include "lib/shared_options.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(SharedOptions, EachSharedOptionIsDocumentedAndNoOtherIs) {
  for (Option o : {Option::tol, Option::width, Option::height}) EXPECT_FALSE(shared_option_help(o).empty());
  // A discrete option's help is in its own table: asking here is a programming error, named.
  try {
    shared_option_help(Option::table_size);
    ADD_FAILURE() << "table_size has no shared help";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "shared_option_help: 'table_size' is not a shared option");
  }
}

}  // namespace
}  // namespace vrv
