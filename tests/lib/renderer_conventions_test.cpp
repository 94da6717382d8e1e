// The renderer conventions of DiscreteConfig, each against a derivation: opacity per unit
// distance (1 - (1 - a)^(H/L)), transfer-function tables read with and without half-texel
// centring, straight against premultiplied colour.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "lib/discrete_raycast.h"
#include "lib/reference_integrator.h"
#include "lib/transfer_table.h"

namespace vrv {
namespace {

const Box kBox;
const MarschnerLobb kSmooth{2, 0.25};  // low frequency: the asymptotic range starts early
const Ray kRay = make_ray(Vec3(-3, 0.13, 0.21), Vec3(1, 0.07, -0.05));

TransferFunction opacity_color(double unit_length) {  // smooth over the field's values [0, 1]
  return TransferFunction::opacity_color(PiecewiseLinear({{-0.5, 0.02}, {1.5, 0.3}}),
                                         PiecewiseLinear({{-0.5, 1.0}, {1.5, 0.2}}), unit_length);
}

DiscreteConfig alpha(Strategy strategy, double h) {
  DiscreteConfig c;
  c.rule = SegmentRule::alpha;
  c.sampling.strategy = strategy;
  c.sampling.step = h;
  return c;
}

double cast(const TransferFunction& tf, const DiscreteConfig& c) {
  return DiscreteRaycaster(kSmooth, kBox, tf, 0.0, c).cast(kRay).value;
}

TEST(OpacityUnit, ConstantMediumMatchesTheClosedFormOfEachConvention) {
  // A constant field and transfer function: n samples of alpha each give
  // I = c (1 - (1 - alpha)^n) + I0 (1 - alpha)^n, with alpha = a per sample, or
  // alpha = 1 - (1 - a)^(H/L) per unit distance (so equal to a at H = L).
  const LinearRamp constant{Vec3::Zero(), 0.5};
  const double a = 0.3, c = 0.7, L = 0.05, I0 = 0.2;
  const auto tf = TransferFunction::opacity_color(PiecewiseLinear({{0, a}}), PiecewiseLinear({{0, c}}), L);
  const Ray ray = make_ray(Vec3(-3, 0.1, 0.2), Vec3(1, 0, 0));  // chord [2, 4]
  for (double H : {L, L / 2, 0.08}) {
    DiscreteConfig cfg = alpha(Strategy::step, H);
    for (OpacityUnit unit : {OpacityUnit::per_sample, OpacityUnit::per_unit_distance}) {
      cfg.opacity_unit = unit;
      const DiscreteResult r = DiscreteRaycaster(constant, kBox, tf, I0, cfg).cast(ray);
      const double al = unit == OpacityUnit::per_sample ? a : 1 - std::pow(1 - a, H / L);
      const double T = std::pow(1 - al, static_cast<double>(r.samples));
      EXPECT_EQ(r.samples, std::lround(2 / H)) << H;
      EXPECT_NEAR(r.value, c * (1 - T) + I0 * T, 1e-14) << "H = " << H << ", " << opacity_unit_name(unit);
    }
  }
}

TEST(OpacityUnit, CorrectedAlphaConvergesToTheReferenceAtSecondOrderAndPerSampleDoesNot) {
  // The reference reads the same transfer function as tau = -ln(1 - a) / L, g = colour tau, and
  // alpha = 1 - (1 - a)^(H/L) = 1 - exp(-tau H) is the alpha rule on it: second order at
  // midpoint samples (inviwo), as for emission/extinction scenes.
  const TransferFunction tf = opacity_color(0.1);
  const double reference = integrate_reference(kSmooth, kBox, tf, 0.0, kRay, {1e-14}).value;
  std::vector<double> corrected, per_sample;
  for (double h : {0.02, 0.01, 0.005, 0.0025}) {
    DiscreteConfig c = alpha(Strategy::inviwo, h);
    per_sample.push_back(std::abs(cast(tf, c) - reference));
    c.opacity_unit = OpacityUnit::per_unit_distance;
    corrected.push_back(std::abs(cast(tf, c) - reference));
  }
  for (std::size_t i = 1; i < corrected.size(); ++i)
    EXPECT_NEAR(std::log2(corrected[i - 1] / corrected[i]), 2.0, 0.25) << i;
  // Opacity per sample: more samples, more opaque; it settles on another value, not the reference.
  const std::size_t last = per_sample.size() - 1;
  EXPECT_GT(per_sample[last], 0.9 * per_sample[last - 1]);
  EXPECT_GT(per_sample[last], 100 * corrected[last]);
}

TEST(OpacityUnit, IsRefusedWhereItMeansNothing) {
  DiscreteConfig c = alpha(Strategy::step, 0.1);
  c.opacity_unit = OpacityUnit::per_unit_distance;
  const auto ee = TransferFunction::emission_extinction(PiecewiseLinear({{0, 1}}), PiecewiseLinear({{0, 1}}));
  EXPECT_THROW(DiscreteRaycaster(kSmooth, kBox, ee, 0.0, c), std::invalid_argument);
  c.rule = SegmentRule::trapezoid;
  EXPECT_THROW(validate(c, false), std::invalid_argument);
}

TEST(TransferTable, CentredReadsALinearCurveExactlyAndUncentredIsShiftedByUMinusHalfAnEntry) {
  const PiecewiseLinear line({{-1, 2}, {3, 10}});  // slope 2
  const int N = 9;
  const TransferTable centred(line, -1, 3, N, TableLookup::centred);
  const TransferTable uncentred(line, -1, 3, N, TableLookup::uncentred);
  const double entry = 4.0 / (N - 1);
  for (double v = -1; v <= 3; v += 0.0625) {
    EXPECT_NEAR(centred(v), line(v), 1e-13) << v;
    // x_uncentred - x_centred = u N - 1/2 - u (N - 1) = u - 1/2 entries (u = (v - lo)/(hi - lo)),
    // except where the clamp to the end entries cuts it off.
    const double u = (v + 1) / 4, x = u * N - 0.5;
    if (x >= 0 && x <= N - 1) {
      EXPECT_NEAR(uncentred(v) - line(v), 2 * entry * (u - 0.5), 1e-13) << v;
    }
  }
  EXPECT_EQ(centred(-5), 2);   // clamp to edge
  EXPECT_EQ(uncentred(7), 10);
  EXPECT_THROW(TransferTable(line, -1, 3, 1, TableLookup::centred), std::invalid_argument);
}

TEST(TransferTable, RaycastsThroughLargerTablesConvergeToTheContinuousTransferFunction) {
  // Emission rising on both sides of a kink at 0.37 (not on any table node), constant extinction,
  // a table range [-1, 1] wider than the field's values [0, 1] (so u >= 1/2): the uncentred
  // table reads g(v + (u - 1/2) entry) >= g(v), an error of one sign, first order in 1/N;
  // the centred table errs only in the kink's cell.
  const auto tf = TransferFunction::emission_extinction(PiecewiseLinear({{-1, 0.2}, {0.37, 1.0}, {1, 1.5}}),
                                                        PiecewiseLinear({{-1, 1.0}, {1, 1.0}}));
  const DiscreteConfig base = alpha(Strategy::inviwo, 0.01);
  const double continuous = cast(tf, base);
  std::vector<double> err_c, err_u;
  for (int N : {64, 128, 256, 512, 1024}) {
    DiscreteConfig c = base;
    c.table_size = N;
    err_c.push_back(std::abs(cast(tf, c) - continuous));
    c.table_lookup = TableLookup::uncentred;
    err_u.push_back(std::abs(cast(tf, c) - continuous));
  }
  for (std::size_t i = 1; i < err_u.size(); ++i) {
    EXPECT_NEAR(std::log2(err_u[i - 1] / err_u[i]), 1.0, 0.2) << i << ": " << err_u[i - 1] << " " << err_u[i];
    EXPECT_LT(err_c[i], err_u[i]) << i;
  }
  EXPECT_LT(err_c.back(), 1e-2 * err_u.back());
}

TEST(ColorConvention, PremultipliedEqualsStraightWhenAlphaIsTheStoredOpacity) {
  const TransferFunction tf = opacity_color(0.1);
  DiscreteConfig c = alpha(Strategy::step, 0.03);
  const double straight = cast(tf, c);
  c.color = ColorConvention::premultiplied;
  EXPECT_EQ(cast(tf, c), straight);  // per sample, no correction: colour * a = colour * alpha
}

TEST(ColorConvention, PremultipliedWithSchulzeIsStraightWithLacroute) {
  // Schulze scales the colour by alpha'/alpha; premultiplied emits colour * (alpha'/alpha) * a
  // with a = alpha (the stored opacity is the per-sample one): colour * alpha', Lacroute's
  // straight emission, with the same transparency 1 - alpha'.
  const TransferFunction tf = opacity_color(0.1);
  DiscreteConfig c = alpha(Strategy::step, 0.03);
  c.oversample = 4;
  c.correction = Correction::lacroute;
  const double straight = cast(tf, c);
  c.correction = Correction::schulze;
  c.color = ColorConvention::premultiplied;
  EXPECT_NEAR(cast(tf, c), straight, 1e-14);
}

TEST(ColorConvention, PremultipliedWithoutRescalingBrightensAsTheStepShrinks) {
  // Opacity corrected to H, colour left at the stored a: each sample emits colour * a while the
  // transparency per sample tends to 1, so the emitted total grows like L / H (a classic fault).
  const TransferFunction tf = opacity_color(0.1);
  const double reference = integrate_reference(kSmooth, kBox, tf, 0.0, kRay, {1e-14}).value;
  std::vector<double> errors;
  for (double h : {0.02, 0.01, 0.005}) {
    DiscreteConfig c = alpha(Strategy::inviwo, h);
    c.opacity_unit = OpacityUnit::per_unit_distance;
    c.color = ColorConvention::premultiplied;
    errors.push_back(cast(tf, c) - reference);
  }
  EXPECT_GT(errors[0], 0);
  EXPECT_GT(errors[1], 1.5 * errors[0]);
  EXPECT_GT(errors[2], 1.5 * errors[1]);
}

TEST(ColorConvention, PreClassifiedPremultipliedInterpolatesTheProduct) {
  // With a constant opacity, interpolating colour * a is a * (interpolated colour): the same image.
  const auto tf = TransferFunction::opacity_color(PiecewiseLinear({{0, 0.2}}), PiecewiseLinear({{0, 0.1}, {1, 0.9}}), 0.1);
  const GridField grid(kBox, {5, 6, 7}, GridLayout::node, Interpolation::trilinear,
                       [](const Vec3& p) { return kSmooth.value(p); });
  DiscreteConfig c = alpha(Strategy::step, 0.03);
  c.classification = Classification::pre;
  const double straight = DiscreteRaycaster(grid, kBox, tf, 0.0, c).cast(kRay).value;
  c.color = ColorConvention::premultiplied;
  EXPECT_NEAR(DiscreteRaycaster(grid, kBox, tf, 0.0, c).cast(kRay).value, straight, 1e-14);
}

}  // namespace
}  // namespace vrv
