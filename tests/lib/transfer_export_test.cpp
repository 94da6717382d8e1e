#include "lib/transfer_export.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vrv {
namespace {

TransferFunction with_jump() {
  return TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {0.5, 1}, {0.5, 2}, {1, 2}}), PiecewiseLinear({{0, 0}, {1, 3}}));
}

// The default scene's g = v, tau = v / 2: colour 2 everywhere, including v = 0 where tau = 0 (it
// was written 0 there, a dip a renderer interpolates into and a floor of 1.3e-5 RMS).
TEST(TransferExport, ColourWhereExtinctionVanishesIsItsLimit) {
  const TransferFunction tf = TransferFunction::emission_extinction(PiecewiseLinear({{0, 0}, {1, 1}}),
                                                                   PiecewiseLinear({{0, 0}, {1, 0.5}}));
  const auto rows = tabulate_transfer(tf, 1, 8);
  ASSERT_EQ(rows.front().value, 0);
  for (const auto& r : rows) EXPECT_DOUBLE_EQ(r.color, 2) << r.value;
  EXPECT_EQ(transfer_json(tf, 1, 8)["emission_without_extinction"], false);
  // Emission without extinction stays inexpressible: colour 0 there, and flagged.
  const TransferFunction bad = TransferFunction::emission_extinction(PiecewiseLinear({{0, 0.5}, {1, 1}}),
                                                                    PiecewiseLinear({{0, 0}, {1, 0.5}}));
  EXPECT_EQ(tabulate_transfer(bad, 1, 8).front().color, 0);
  EXPECT_EQ(transfer_json(bad, 1, 8)["emission_without_extinction"], true);
}

TEST(TransferExport, RowsFollowTheFunctionAndAJumpGivesTwoRows) {
  const TransferFunction tf = with_jump();
  const auto rows = tabulate_transfer(tf, 0.25, 4);
  int at_half = 0;
  for (const auto& r : rows) {
    EXPECT_DOUBLE_EQ(r.extinction, tf.extinction(r.value)) << r.value;  // no jump in tau
    EXPECT_DOUBLE_EQ(r.opacity, 1 - std::exp(-r.extinction * 0.25));
    if (r.extinction > 0) {
      EXPECT_DOUBLE_EQ(r.color, r.emission / r.extinction);
    }
    at_half += r.value == 0.5;
  }
  ASSERT_EQ(at_half, 2);
  // Left limit then right limit at the jump.
  for (std::size_t i = 0; i + 1 < rows.size(); ++i)
    if (rows[i].value == 0.5 && rows[i + 1].value == 0.5) {
      EXPECT_DOUBLE_EQ(rows[i].emission, 1);
      EXPECT_DOUBLE_EQ(rows[i + 1].emission, 2);
    }
  EXPECT_EQ(rows.front().value, 0);
  EXPECT_EQ(rows.back().value, 1);
}

TEST(TransferExport, OpacityColourScenesKeepTheirControlPointsExactly) {
  const auto tf = TransferFunction::opacity_color(PiecewiseLinear({{0, 0}, {1, 0.4}}),
                                                  PiecewiseLinear({{0, 1}, {0.3, 0.2}}), 0.125);
  const auto j = transfer_json(tf, 99, 8);
  EXPECT_EQ(j["exact"], true);
  EXPECT_EQ(j["unit_distance"], 0.125);  // the scene's own, not the option
  EXPECT_EQ(j["opacity"][1][1], 0.4);
  EXPECT_EQ(j["color"][1][0], 0.3);
}

TEST(TransferExport, TabulatedOpacityStatesItsInterpolationError) {
  const auto coarse = transfer_json(with_jump(), 1, 32);
  const auto fine = transfer_json(with_jump(), 1, 64);
  EXPECT_EQ(coarse["exact"], false);
  const double e32 = coarse["max_interpolation_error"]["opacity"], e64 = fine["max_interpolation_error"]["opacity"];
  EXPECT_GT(e64, 0);
  // Linear interpolation of a smooth curve: the gap falls as (rows per segment)^-2.
  EXPECT_NEAR(e32 / e64, 4.0, 0.2);
  EXPECT_EQ(coarse["emission_without_extinction"], false);
}

}  // namespace
}  // namespace vrv
