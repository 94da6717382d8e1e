#include "lib/gate.h"

#include <cmath>

#include <gtest/gtest.h>

namespace vrv {
namespace {

TEST(JudgeBound, UpperLimitsByLevel) {
  const Limits l{1e-4, 1e-3, 1e-2};
  EXPECT_EQ(judge_bound("c", Bound::rms, "w", 5e-5, l).verdict, BoundVerdict::pass);
  EXPECT_EQ(judge_bound("c", Bound::rms, "w", 5e-4, l).verdict, BoundVerdict::warn);
  EXPECT_EQ(judge_bound("c", Bound::rms, "w", 5e-3, l).verdict, BoundVerdict::fail);
  EXPECT_EQ(judge_bound("c", Bound::rms, "w", 5e-2, l).verdict, BoundVerdict::hard_fail);
  const BoundRow pass = judge_bound("c", Bound::rms, "w", 5e-5, l);
  EXPECT_DOUBLE_EQ(pass.limit, 1e-3);
  EXPECT_DOUBLE_EQ(pass.margin, 1e-3 - 5e-5);
  const BoundRow fail = judge_bound("c", Bound::rms, "w", 5e-3, l);
  EXPECT_DOUBLE_EQ(fail.limit, 1e-3);
  EXPECT_LT(fail.margin, 0);
  EXPECT_EQ(judge_bound("c", Bound::rms, "w", NAN, l).verdict, BoundVerdict::hard_fail);
}

TEST(JudgeBound, LowerLimitsForTheOrder) {
  const Limits l{1.9, 1.75, std::nullopt};
  EXPECT_EQ(judge_bound("c", Bound::min_order, "w", 2.0, l).verdict, BoundVerdict::pass);
  EXPECT_EQ(judge_bound("c", Bound::min_order, "w", 1.8, l).verdict, BoundVerdict::warn);
  EXPECT_EQ(judge_bound("c", Bound::min_order, "w", 1.0, l).verdict, BoundVerdict::fail);
  EXPECT_DOUBLE_EQ(judge_bound("c", Bound::min_order, "w", 2.0, l).margin, 0.25);
}

TEST(JudgeBound, ABoundTightenedPastTheMeasuredValueFails) {
  const double measured = 3.2e-4;
  EXPECT_EQ(judge_bound("c", Bound::max, "w", measured, Limits{{}, measured * 1.01, {}}).verdict, BoundVerdict::pass);
  EXPECT_EQ(judge_bound("c", Bound::max, "w", measured, Limits{{}, measured * 0.99, {}}).verdict, BoundVerdict::fail);
}

TEST(BoundTable, OneRowPerBound) {
  std::vector<BoundRow> rows{judge_bound("c", Bound::rms, "w", 1, Limits{{}, 2, {}}),
                             judge_bound("c", Bound::max, "w", 3, Limits{1, 2, 4})};
  const Table t = bound_table(rows);
  EXPECT_EQ(t.size(), 2u);
  EXPECT_EQ(worst(rows), BoundVerdict::fail);
  EXPECT_NE(t.to_csv().find("c,rms,w,1,2,1,,2,,pass"), std::string::npos) << t.to_csv();
}

}  // namespace
}  // namespace vrv
