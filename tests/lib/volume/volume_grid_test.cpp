#include "lib/volume/volume_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "analytic/marschner_lobb.h"
#include "lib/scene.h"

namespace vrv {
namespace {

// 3 x 2 x 4 int16 samples s = 100 i + 10 j + k; index axes along -y, +z, -x.
Volume permuted() {
  Volume v;
  v.dims = {3, 2, 4};
  v.axis = {1, 2, 0};
  v.sign = {-1, 1, -1};
  v.spacing = Vec3(0.5, 2.0, 0.25);
  v.origin = Vec3(10, 20, 30);
  std::vector<std::int16_t> s;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) s.push_back(static_cast<std::int16_t>(100 * i + 10 * j + k));
  v.samples = s;
  return v;
}

// A message names a scene's volume files from its digest (the study's memory refusal said "the
// volume" alone).
TEST(VolumeGrid, TheDigestNamesItsFiles) {
  EXPECT_EQ(digest_file_names("head.nhdr:00112233445566ff;head.raw:0123456789abcdef;"), "head.nhdr, head.raw");
  EXPECT_EQ(digest_file_names("a:b;c.nii:0000000000000000;"), "a:b;c.nii");  // names may hold ':' and ';'
  EXPECT_EQ(digest_file_names(""), "");
}

TEST(VolumeGrid, TheHeaderBoxHoldsTheFirstAndLastSamplesOnItsFaces) {
  const Box node = volume_box(permuted(), GridLayout::node);
  // x: index k (-x, 4 samples, 0.25): [10 - 0.75, 10]; y: index i (-y, 3, 0.5): [19, 20];
  // z: index j (+z, 2, 2): [30, 32].
  EXPECT_EQ(node.min, Vec3(9.25, 19, 30));
  EXPECT_EQ(node.max, Vec3(10, 20, 32));
  const Box cell = volume_box(permuted(), GridLayout::cell);
  EXPECT_EQ(cell.min, Vec3(9.125, 18.75, 29));
  EXPECT_EQ(cell.max, Vec3(10.125, 20.25, 33));
}

// Every sample is found again at its world position (nearest: the node itself), for every
// permutation of the index axes and every choice of mirrored axes (the samples are put in grid
// order where they are, cycle by cycle).
TEST(VolumeGrid, HeaderPlacementPutsEverySampleAtItsWorldPosition) {
  std::array<int, 3> axis{0, 1, 2};
  int cases = 0;
  do {
    for (int signs = 0; signs < 8; ++signs) {
      Volume v = permuted();
      v.axis = axis;
      for (int a = 0; a < 3; ++a) v.sign[a] = signs >> a & 1 ? -1 : 1;
      for (GridLayout layout : {GridLayout::node, GridLayout::cell}) {
        const GridField g = volume_grid(v, {}, VolumePlacement::header, Box{}, layout, Interpolation::nearest, "v.nrrd");
        GridField::Index3 n{};
        for (int a = 0; a < 3; ++a) n[axis[a]] = v.dims[a];
        EXPECT_EQ(g.resolution(), n);
        const Eigen::Matrix3d steps = v.steps();
        for (int k = 0; k < 4; ++k)
          for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
              const Vec3 p = v.origin + steps * Vec3(i, j, k);
              EXPECT_EQ(g.value(p), v.sample(i, j, k)) << i << " " << j << " " << k << " signs " << signs;
            }
      }
      ++cases;
    }
  } while (std::next_permutation(axis.begin(), axis.end()));
  EXPECT_EQ(cases, 48);
}

// The grid keeps the samples in their own type (2 bytes a node and the 65 536-entry table for
// int16), placed by the header (put in grid order where they are) or in a box (moved, file order).
TEST(VolumeGrid, TheGridHoldsTheSamplesInTheirOwnType) {
  for (VolumePlacement placement : {VolumePlacement::header, VolumePlacement::box}) {
    const GridField g = volume_grid(permuted(), {}, placement, Box{}, GridLayout::node, Interpolation::trilinear, "v.nrrd");
    EXPECT_EQ(g.nodes().kind(), GridNodes::Kind::code16);
    EXPECT_EQ(g.nodes().bytes(), 24 * sizeof(std::int16_t) + 65536 * sizeof(double));
  }
}

TEST(VolumeGrid, BoxPlacementKeepsIndexOrder) {
  const Volume v = permuted();
  const Box box{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  const GridField g = volume_grid(v, {}, VolumePlacement::box, box, GridLayout::node, Interpolation::trilinear, "v");
  EXPECT_EQ(g.box().min, box.min);
  EXPECT_EQ(g.resolution(), (GridField::Index3{3, 2, 4}));
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) EXPECT_EQ(g.node(i, j, k), v.sample(i, j, k));
}

TEST(VolumeGrid, MapsRawRescaleAndWindowPerSample) {
  Volume v = permuted();
  v.has_rescale = true;
  v.slope = 2.5;
  v.intercept = -10;
  const Box box;
  auto node = [&](VolumeMapping m, int i, int j, int k) {
    return volume_grid(v, m, VolumePlacement::box, box, GridLayout::node, Interpolation::trilinear, "v").node(i, j, k);
  };
  EXPECT_EQ(node({VolumeValue::raw}, 2, 1, 3), 213);
  EXPECT_EQ(node({VolumeValue::rescale}, 2, 1, 3), 2.5 * 213 - 10);
  // Window over rescaled values: 2.5 * 100 - 10 = 240 maps to (240 - 40) / 400 = 0.5; clamped.
  EXPECT_EQ(node({VolumeValue::window, 40, 440}, 1, 0, 0), 0.5);
  EXPECT_EQ(node({VolumeValue::window, 40, 440}, 0, 0, 0), 0.0);
  EXPECT_EQ(node({VolumeValue::window, 40, 440}, 2, 1, 3), 1.0);
  v.has_rescale = false;  // a window over raw values then
  EXPECT_EQ(node({VolumeValue::window, 0, 200}, 1, 0, 0), 0.5);
}

TEST(VolumeGrid, RefusesARescaleTheFileLacksAndNonFiniteSamples) {
  Volume v = permuted();
  try {
    volume_grid(v, {VolumeValue::rescale}, VolumePlacement::box, Box{}, GridLayout::node, Interpolation::nearest, "v.mha");
    FAIL();
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()),
              "v.mha: value: rescale: the file's header has no slope and intercept (use raw or a window)");
  }
  std::vector<float> f(24, 1.0f);
  f[7] = std::numeric_limits<float>::quiet_NaN();
  v.samples = f;
  try {
    volume_grid(v, {}, VolumePlacement::box, Box{}, GridLayout::node, Interpolation::nearest, "v.mha");
    FAIL();
  } catch (const VolumeFileError& e) {
    EXPECT_EQ(std::string(e.what()), "v.mha: (data): sample (1, 0, 1) is nan");
  }
}

TEST(VolumeGrid, OneSampleOnAnAxisNeedsCellLayout) {
  Volume v;
  v.dims = {2, 2, 1};
  v.samples = std::vector<std::uint8_t>{1, 2, 3, 4};
  EXPECT_THROW(volume_box(v, GridLayout::node), std::invalid_argument);
  const Box cell = volume_box(v, GridLayout::cell);
  EXPECT_EQ(cell.min, Vec3(-0.5, -0.5, -0.5));
  EXPECT_EQ(cell.max, Vec3(1.5, 1.5, 0.5));
}

// The constructor from node values is the sampling constructor's grid, bit for bit.
TEST(GridFieldFromValues, EqualsTheSampledGridBitForBit) {
  const MarschnerLobb ml;
  const Box box{Vec3(-1, -2, -0.5), Vec3(1.5, 2, 3)};
  for (GridLayout layout : {GridLayout::node, GridLayout::cell})
    for (Interpolation interp : {Interpolation::trilinear, Interpolation::nearest}) {
      const GridField sampled(box, {7, 5, 6}, layout, interp, [&](const Vec3& p) { return ml.value(p); });
      std::vector<double> values;
      for (int k = 0; k < 6; ++k)
        for (int j = 0; j < 5; ++j)
          for (int i = 0; i < 7; ++i) values.push_back(sampled.node(i, j, k));
      const GridField given(box, {7, 5, 6}, layout, interp, values);
      std::mt19937_64 rng(7);
      std::uniform_real_distribution<double> u(0, 1);
      for (int n = 0; n < 200; ++n) {
        const Vec3 p = box.min + box.extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        EXPECT_EQ(given.value(p), sampled.value(p));
      }
      EXPECT_EQ(given.max_change_within(0.1), sampled.max_change_within(0.1));
      EXPECT_EQ(given.value_noise(), sampled.value_noise());
    }
}

TEST(GridFieldFromValues, RefusesAWrongCountOrANonFiniteValue) {
  const Box box;
  EXPECT_THROW(GridField(box, {2, 2, 2}, GridLayout::node, Interpolation::trilinear, std::vector<double>(7, 0.0)),
               std::invalid_argument);
  std::vector<double> v(8, 0.0);
  v[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(GridField(box, {2, 2, 2}, GridLayout::node, Interpolation::trilinear, v), std::invalid_argument);
  EXPECT_THROW(GridField(box, {1, 2, 2}, GridLayout::node, Interpolation::trilinear, std::vector<double>(4, 0.0)),
               std::invalid_argument);
}

}  // namespace
}  // namespace vrv
