// The oracle itself (independent_reference.h): against closed forms, its grid path against a ramp,
// its fields pointwise against vrv's, and converged (a finer scan, shorter panels and more points
// change nothing at long-double level).
#include "tests/lib/independent_reference.h"

#include <gtest/gtest.h>

#include <array>
#include <random>

#include "analytic/linear_ramp.h"
#include "lib/grid_field.h"
#include "tests/lib/reference_check.h"

namespace vrv {
namespace {

using namespace reference_check;

LD slab(LD g, LD tau, LD L) { return g / tau * -std::expm1(-tau * L); }

// A ramp seen through a cell-layout grid: the node values sit at the cell centres, so trilinear
// interpolation is the ramp inside the centres' box and, in the outer half cells, the ramp at
// the point clamped onto that box (the clamp of the grid's coordinates).  Its kinks are the
// clamp planes.
class ClampedRampLD final : public ind::FieldLD {
 public:
  ClampedRampLD(const LinearRamp& ramp, const Box& box, const std::array<int, 3>& cells) : ramp_(ramp) {
    for (int a = 0; a < 3; ++a) {
      const LD half = (static_cast<LD>(box.max[a]) - box.min[a]) / (2 * cells[a]);
      lo_[a] = box.min[a] + half;
      hi_[a] = box.max[a] - half;
    }
  }
  LD value(const ind::P3& p, const ind::P3&) const override {
    LD v = ramp_.offset;
    for (int a = 0; a < 3; ++a) v += static_cast<LD>(ramp_.gradient[a]) * std::clamp(p[a], lo_[a], hi_[a]);
    return v;
  }
  void structural_breaks(const ind::P3& o, const ind::P3& d, LD t0, LD t1, std::vector<LD>& out) const override {
    for (int a = 0; a < 3; ++a)
      for (LD plane : {lo_[a], hi_[a]})
        if (d[a] != 0)
          if (const LD t = (plane - o[a]) / d[a]; t > t0 && t < t1) out.push_back(t);
  }

 private:
  LinearRamp ramp_;
  LD lo_[3], hi_[3];
};

TEST(ReferenceIntegratorOracle, ConstantFieldClosedForms) {
  const ind::LinearRampLD ref(Vec3(0, 0, 0), 0.37L);
  const RaySpec spec{{-0.5, -3, 0.25}, {0.1, 1, -0.05}};
  const ind::Result geom =
      ind::independent_integral(ref, kBox, tf_general(), 0, spec.origin, spec.direction);
  const LD L = geom.t_exit - geom.t_entry;
  // Emission / extinction.
  {
    const TransferFunction tf = tf_general();
    // The control values are doubles: use them exactly.
    const LD v = 0.37L, p1 = 0.3, p2 = 0.5, g1 = 0.1, t1 = 0.8, v1 = 0.4;
    const LD g = g1 + (1 - g1) * (v - p1) / (p2 - p1);
    const LD tau = t1 * v / v1;
    const ind::Result r = ind::independent_integral(ref, kBox, tf, 0.3, spec.origin, spec.direction);
    const LD exact = slab(g, tau, L) + 0.3L * std::exp(-tau * L);
    EXPECT_LE(std::abs(r.value - exact), 1e-17L * (1 + std::abs(exact)));
    EXPECT_LE(std::abs(r.optical_depth - tau * L), 1e-17L * tau * L);
  }
  // Opacity / colour.
  {
    const LD v = 0.37L, a = LD{0.3} * v, c = 1 + (LD{0.2} - 1) * v, Lu = 0.05;
    const LD tau = -std::log1p(-a) / Lu;
    const ind::Result r =
        ind::independent_integral(ref, kBox, tf_opacity(), 0, spec.origin, spec.direction);
    const LD exact = slab(c * tau, tau, L);
    EXPECT_LE(std::abs(r.value - exact), 1e-17L * (1 + exact));
  }
}

TEST(ReferenceIntegratorOracle, LinearRampClosedForms) {
  // v = 0.5 + 0.25 x along the x axis from x = -1 to 1.
  const ind::LinearRampLD ref(Vec3(0.25, 0, 0), 0.5L);
  const RaySpec spec{{-3, 0.1, -0.2}, {1, 0, 0}};
  // Linear g, constant tau: int_0^2 (g0 + k s) e^{-tau s} ds.
  {
    const TransferFunction tf = TransferFunction::emission_extinction(
        curve({{-10, 0}, {10, 20}}), curve({{0, 0.7}}));
    const LD tau = 0.7, L = 2, g0 = 10 + 0.25L, k = 0.25L;  // g = v + 10
    const LD e = std::exp(-tau * L);
    const LD exact = g0 * (1 - e) / tau + k * (1 - e * (1 + tau * L)) / (tau * tau);
    const ind::Result r = ind::independent_integral(ref, kBox, tf, 0, spec.origin, spec.direction);
    EXPECT_LE(std::abs(r.value - exact), 1e-17L * exact);
  }
  // The step transfer function: the crossing at x = 0 cuts the ray into two slabs of length 1.
  {
    const LD exact = std::exp(-LD{0.1}) * slab(1, 2, 1);
    const ind::Result r =
        ind::independent_integral(ref, kBox, tf_step(), 0, spec.origin, spec.direction);
    EXPECT_LE(std::abs(r.value - exact), 1e-18L);
    EXPECT_LE(std::abs(r.optical_depth - (LD{0.1} + 2)), 1e-17L);
  }
}

TEST(ReferenceIntegratorOracle, TrilinearGridReproducesRamp) {
  // Trilinear interpolation reproduces a linear field; the grid path (planes, cells, clamp)
  // must then agree with the ramp path: the ramp itself for node layout, the ramp clamped onto
  // the cell centres' box for cell layout (written independently above).
  const LinearRamp ramp{{0.3, 0.2, -0.1}, 0.5};
  const std::array<int, 3> res{5, 4, 6};
  const ind::LinearRampLD node_ref(ramp.gradient, 0.5L);
  const ClampedRampLD cell_ref(ramp, kBox, res);
  for (auto layout : {GridLayout::node, GridLayout::cell}) {
    const GridField grid = make_grid(kBox, ramp, {res[0], res[1], res[2]}, layout, Interpolation::trilinear);
    const ind::GridLD gref(grid);
    const ind::FieldLD& ref = layout == GridLayout::node ? static_cast<const ind::FieldLD&>(node_ref) : cell_ref;
    for (const auto& spec : random_rays(3, 7)) {
      const ind::Result a =
          ind::independent_integral(gref, kBox, tf_general(), 0, spec.origin, spec.direction);
      const ind::Result b =
          ind::independent_integral(ref, kBox, tf_general(), 0, spec.origin, spec.direction);
      EXPECT_TRUE(a.hit) << (layout == GridLayout::node ? "node" : "cell");
      EXPECT_GT(a.value, 0) << (layout == GridLayout::node ? "node" : "cell");
      EXPECT_NEAR(static_cast<double>(a.value), static_cast<double>(b.value), 1e-14)
          << (layout == GridLayout::node ? "node" : "cell");
    }
  }
}

TEST(ReferenceIntegratorOracle, FieldsAgreePointwise) {
  // The long-double fields are the same functions as vrv's (up to double rounding).
  std::mt19937_64 rng(5);
  const GridField grids[] = {
      make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::trilinear),
      make_grid(kBox, kML, {8, 7, 6}, GridLayout::cell, Interpolation::trilinear),
      make_grid(kBox, kML, {9, 9, 9}, GridLayout::node, Interpolation::nearest),
      make_grid(kBox, kML, {8, 8, 8}, GridLayout::cell, Interpolation::nearest)};
  std::vector<ind::GridLD> refs;
  for (const GridField& g : grids) refs.emplace_back(g);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(2 * uniform(rng) - 1, 2 * uniform(rng) - 1, 2 * uniform(rng) - 1);
    const ind::P3 q = ind::to_p3(p);
    EXPECT_NEAR(static_cast<double>(kMLRef.value(q, q)), kML.value(p), 1e-14);
    for (std::size_t g = 0; g < refs.size(); ++g)
      EXPECT_NEAR(static_cast<double>(refs[g].value(q, q)), grids[g].value(p), 1e-14);
  }
}

TEST(ReferenceIntegratorOracle, ConvergedOnMarschnerLobb) {
  // Finer scan, shorter panels and more points change nothing at long-double level.
  ind::Options fine;
  fine.scan_density = 40000;
  fine.max_panel = 0.01L;
  fine.points = 24;
  int i = 0;
  for (const auto& tf : {tf_step(), tf_peak()}) {
    for (const auto& spec : random_rays(2, 99 + i++)) {
      const ind::Result a =
          ind::independent_integral(kMLRef, kBox, tf, 0, spec.origin, spec.direction);
      const ind::Result b =
          ind::independent_integral(kMLRef, kBox, tf, 0, spec.origin, spec.direction, fine);
      EXPECT_LE(std::abs(a.value - b.value), 1e-17L) << describe(spec);
    }
  }
}

}  // namespace
}  // namespace vrv
