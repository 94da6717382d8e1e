// The grid field as the exact integral sees it: node and cell layouts, trilinear and nearest
// interpolation (their cell planes and half-way planes are the breaks the reference integrates
// between), checked ray by ray against the independent long-double integral (reference_check.h).
#include "lib/grid_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>

#include "tests/lib/reference_check.h"

namespace vrv {
namespace {

using namespace reference_check;

TEST(ReferenceIntegratorGrid, NodeTrilinear) {
  const GridField grid = make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::trilinear);
  check_rays("grid 9^3 node trilinear (b)", grid, ind::GridLD(grid), tf_general(), 0,
             random_rays(15, 21));
}

TEST(ReferenceIntegratorGrid, CellTrilinear) {
  const GridField grid = make_grid(kBox, kML, {8, 8, 8}, GridLayout::cell, Interpolation::trilinear);
  check_rays("grid 8^3 cell trilinear (b)", grid, ind::GridLD(grid), tf_general(), 0,
             random_rays(15, 22));
}

TEST(ReferenceIntegratorGrid, NodeNearest) {
  const GridField grid = make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::nearest);
  check_rays("grid 9^3 node nearest (b)", grid, ind::GridLD(grid), tf_general(), 0,
             random_rays(15, 23));
}

// The grid with everything the reference may use but node_range_between: the reference
// integrates every cell of it, empty or not.
struct WithoutSkipping {
  const GridField& grid;
  double value(const Vec3& p) const { return grid.value(p); }
  int degree_along_ray() const { return grid.degree_along_ray(); }
  double bandwidth() const { return grid.bandwidth(); }
  void append_breaks(const Ray& ray, Interval iv, std::vector<double>& breaks) const {
    grid.append_breaks(ray, iv, breaks);
  }
  double max_change_within(double distance) const { return grid.max_change_within(distance); }
  double value_noise() const { return grid.value_noise(); }
};

// Empty space (cells whose nodes all map to g = tau = 0) is skipped exactly: the same value
// bit for bit as integrating every cell, honest against the independent integral, with the
// evaluations of the other cells only.  Half the grid is 0 (x < 0), the transfer function zero
// up to 0.2; a cell on the boundary (nodes 0 and > 0.2) is integrated.
TEST(ReferenceIntegratorGrid, EmptyCellsAreSkippedExactly) {
  for (Interpolation interpolation : {Interpolation::trilinear, Interpolation::nearest}) {
    const GridField grid(kBox, {21, 6, 5}, GridLayout::node, interpolation, [](const Vec3& p) {
      return p.x() < 0 ? 0.0 : 0.3 + 0.5 * p.x() + 0.1 * std::sin(3 * p.y() + p.z());
    });
    const TransferFunction tf = TransferFunction::emission_extinction(
        curve({{0.0, 0.0}, {0.2, 0.0}, {1.0, 1.0}}), curve({{0.0, 0.0}, {0.2, 0.0}, {1.0, 2.0}}));
    for (const Vec3& direction : {Vec3(1, 0.05, 0.02), Vec3(1, -0.3, 0.2)}) {
      const Ray ray = make_ray(Vec3(-3, 0.1, 0.2), direction);
      const ReferenceResult skipped = integrate_reference(grid, kBox, tf, 0, ray, {1e-12});
      const ReferenceResult every = integrate_reference(WithoutSkipping{grid}, kBox, tf, 0, ray, {1e-12});
      EXPECT_EQ(skipped.value, every.value);
      EXPECT_LE(skipped.error_estimate, every.error_estimate);
      // Ten of the twenty cells along x are empty (for the oblique ray, about as many).
      EXPECT_LT(skipped.evaluations, 0.7 * every.evaluations) << skipped.evaluations << " of " << every.evaluations;
      EXPECT_GT(skipped.value, 0.1);
      const ind::Result truth = ind::independent_integral(ind::GridLD(grid), kBox, tf, 0, ray);
      EXPECT_LE(static_cast<double>(std::abs(static_cast<ind::LD>(skipped.value) - truth.value)),
                skipped.error_estimate + kSlack);
    }
  }
}

// Empty space inside a zero stretch open at both ends (jumps at 0.5 and 0.7, no control point
// between): the gate that spares scenes without empty space the search (may_hold_empty_space)
// still finds it (the grid's range, about 0.2 to 0.9, is transparent at none of its ends nor at the
// jumps: only between them), and those cells are skipped.
TEST(ReferenceIntegratorGrid, EmptySpaceBetweenTwoJumpsIsStillSkipped) {
  const GridField grid(kBox, {21, 6, 5}, GridLayout::node, Interpolation::trilinear, [](const Vec3& p) {
    return p.x() < 0 ? 0.6 : 0.55 + 0.35 * std::sin(3 * p.y() + p.z());  // 0.2 to 0.9 for x >= 0
  });
  const PiecewiseLinear hole = curve({{0.0, 1.0}, {0.5, 1.0}, {0.5, 0.0}, {0.7, 0.0}, {0.7, 1.0}});
  const TransferFunction tf = TransferFunction::emission_extinction(hole, hole);
  const Ray ray = make_ray(Vec3(-3, 0.1, 0.2), Vec3(1, 0.05, 0.02));
  const ReferenceResult skipped = integrate_reference(grid, kBox, tf, 0, ray, {1e-12});
  const ReferenceResult every = integrate_reference(WithoutSkipping{grid}, kBox, tf, 0, ray, {1e-12});
  EXPECT_EQ(skipped.value, every.value);
  EXPECT_LT(skipped.evaluations, 0.7 * every.evaluations) << skipped.evaluations << " of " << every.evaluations;
}

// The grid as the reference saw it before bricks: empty space skipped cell by cell only.
struct CellByCellSkipping : WithoutSkipping {
  std::pair<double, double> node_range_between(const Vec3& p, const Vec3& q) const {
    return grid.node_range_between(p, q);
  }
};

// Bricks skip whole stretches of empty space and change nothing: the value, the estimate and the
// evaluations are those of skipping cell by cell, to the bit, on rays along axes, through brick
// corners and at random, in node and cell layouts (a ball of matter in a 49 x 41 x 37 grid, six
// bricks and a part per axis).
TEST(ReferenceIntegratorGrid, BricksSkipEmptySpaceAsCellsWouldToTheBit) {
  const TransferFunction tf = TransferFunction::emission_extinction(
      curve({{0.0, 0.0}, {0.2, 0.0}, {1.0, 1.0}}), curve({{0.0, 0.0}, {0.2, 0.0}, {1.0, 3.0}}));
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Ray> rays;
  for (int n = 0; n < 60; ++n) rays.push_back(make_ray(Vec3(-3, 0.8 * u(rng), 0.8 * u(rng)), Vec3(1, 0.4 * u(rng), 0.4 * u(rng))));
  for (int a = 0; a < 3; ++a) {
    Vec3 o(0.01, -0.02, 0.03), d = Vec3::Zero();
    o[a] = -3, d[a] = 1;
    rays.push_back(make_ray(o, d));
  }
  rays.push_back(make_ray(Vec3(-3, -3, -3), Vec3(1, 1, 1)));  // through brick corners (cubic grid below)
  for (GridLayout layout : {GridLayout::node, GridLayout::cell}) {
    for (const GridField::Index3 n : {GridField::Index3{49, 41, 37}, GridField::Index3{33, 33, 33}}) {
      const GridField grid(kBox, n, layout, Interpolation::trilinear, [](const Vec3& p) {
        const double r = p.norm();
        return r > 0.45 ? 0.0 : 0.3 + 0.6 * (0.45 - r) + 0.05 * std::sin(7 * p.x());
      });
      int rays_with_spans = 0;
      for (const Ray& ray : rays) {
        const ReferenceResult bricks = integrate_reference(grid, kBox, tf, 0, ray, {1e-12});
        const ReferenceResult cells = integrate_reference(CellByCellSkipping{{grid}}, kBox, tf, 0, ray, {1e-12});
        EXPECT_EQ(bricks.value, cells.value);
        EXPECT_EQ(bricks.error_estimate, cells.error_estimate);
        EXPECT_EQ(bricks.evaluations, cells.evaluations);
        std::vector<Interval> spans;
        if (const auto iv = clip(ray, kBox))
          grid.append_transparent_spans(ray, *iv, [&](double lo, double hi) { return tf.transparent_on(lo, hi); }, spans);
        rays_with_spans += !spans.empty();
      }
      // The test means something only where bricks were skipped: on most rays (37 to 46 of 64).
      EXPECT_GT(rays_with_spans, static_cast<int>(rays.size()) / 2) << "bricks skipped on too few rays";
    }
  }
}

// The planes a ray crosses come sorted (each axis's run in the ray's order, merged), whatever
// the direction's signs: the reference's cuts are then not sorted again.  The same t as every
// plane crossing found one by one.
TEST(GridField, BreaksComeSortedAndComplete) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1, 1);
  const Box box{Vec3(-1, -0.5, 0), Vec3(1, 0.7, 2)};
  for (Interpolation interp : {Interpolation::trilinear, Interpolation::nearest})
    for (GridLayout layout : {GridLayout::node, GridLayout::cell}) {
      const GridField grid = make_grid(box, kML, {7, 5, 9}, layout, interp);
      for (int r = 0; r < 200; ++r) {
        Vec3 d(u(rng), u(rng), u(rng));
        if (r % 7 == 0) d[r % 3] = 0;  // a ray parallel to a plane family
        if (d.norm() == 0) continue;
        const Ray ray = make_ray(Vec3(3 * u(rng), 3 * u(rng), 1 + 3 * u(rng)), d.normalized());
        const auto iv = clip(ray, box);
        if (!iv) continue;
        std::vector<double> breaks{-7.0};  // a value before: only what is appended is sorted
        grid.append_breaks(ray, *iv, breaks);
        ASSERT_TRUE(std::is_sorted(breaks.begin() + 1, breaks.end())) << r;
        // Every plane crossing strictly inside iv, axis by axis, by the same expression.
        std::vector<double> expected;
        for (int a = 0; a < 3; ++a) {
          if (ray.direction[a] == 0) continue;
          const int n = grid.resolution()[a];
          const double h = layout == GridLayout::node ? box.extent()[a] / (n - 1) : box.extent()[a] / n;
          const double shift = (layout == GridLayout::node ? 0.0 : 0.5) + (interp == Interpolation::nearest ? 0.5 : 0.0);
          const int planes = interp == Interpolation::nearest ? n - 1 : n;
          for (int m = 0; m < planes; ++m) {
            const double t = (box.min[a] + (m + shift) * h - ray.origin[a]) / ray.direction[a];
            if (t > iv->t0 && t < iv->t1) expected.push_back(t);
          }
        }
        std::sort(expected.begin(), expected.end());
        EXPECT_EQ(std::vector<double>(breaks.begin() + 1, breaks.end()), expected) << r;
      }
    }
}

// with_fetch hands a loop the same values as value(), for every node type and interpolation.
TEST(GridField, FetchIsValueForEveryNodeTypeAndInterpolation) {
  const GridField::Index3 n{5, 6, 4};
  const std::size_t count = static_cast<std::size_t>(n[0]) * n[1] * n[2];
  std::mt19937_64 rng(41);
  std::vector<std::uint8_t> u8;
  std::vector<std::int16_t> i16;
  std::vector<float> f32;
  std::vector<double> f64;
  for (std::size_t i = 0; i < count; ++i) {
    u8.push_back(static_cast<std::uint8_t>(rng() % 256));
    i16.push_back(static_cast<std::int16_t>(static_cast<int>(rng() % 4096) - 2048));
    f32.push_back(static_cast<float>(rng() % 1000) / 7.0f);
    f64.push_back(static_cast<double>(rng() % 1000) / 3.0);
  }
  const SampleMap map{true, 0.25, -3, false, 0, 1};
  const std::vector<GridNodes> kinds{GridNodes(f64), GridNodes(VolumeSamples(u8), map),
                                     GridNodes(VolumeSamples(i16), map), GridNodes(VolumeSamples(f32), map)};
  const Box box{Vec3(-1, 0, 2), Vec3(2, 1.5, 3)};
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  for (const GridNodes& nodes : kinds)
    for (GridLayout layout : {GridLayout::node, GridLayout::cell})
      for (Interpolation interp : {Interpolation::trilinear, Interpolation::nearest}) {
        const GridField grid(box, n, layout, interp, nodes);
        int calls = 0;
        grid.with_fetch([&](const auto& fetch) {
          ++calls;
          for (int k = 0; k < 300; ++k) {
            const Vec3 p = box.min + box.extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
            EXPECT_EQ(std::bit_cast<std::uint64_t>(fetch(p)), std::bit_cast<std::uint64_t>(grid.value(p)));
          }
        });
        EXPECT_EQ(calls, 1);
      }
}

}  // namespace
}  // namespace vrv
