#pragma once
// The shading factor S along one ray, as the reference integrator weighs the emission with it:
// S from the field's exact gradient at the quadrature's own nodes, and S's switches (kinks of
// max(0, .), a two-sided normal's flip) as breaks, so that every piece is integrated on one smooth
// branch.  The integrator sees the abstract EmissionWeight (one virtual call per piece, not per
// value); FieldShading<F> is the field-typed implementation.
#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>
#include <span>
#include <vector>

#include "lib/chebyshev.h"
#include "lib/field.h"
#include "lib/ray_panel.h"
#include "lib/shading.h"
#include "lib/weight_switch.h"

namespace vrv {

class EmissionWeight {
 public:
  virtual ~EmissionWeight() = default;
  // S at ts (all in [c, d], a piece between two switches, whose branch the middle decides) and
  // each value's absolute rounding.
  virtual void values(double c, double d, std::span<const double> ts, std::span<double> s,
                      std::span<double> noise) const = 0;
  // The switches in (a, b), appended in no particular order.
  virtual void append_switches(double a, double b, std::vector<WeightSwitch>& out) const = 0;
  virtual double max() const = 0;  // S <= max everywhere
  virtual double min() const = 0;  // S >= min >= 0 everywhere
};

// A field with an exact gradient: piece_gradient(p, inside) is grad f at p of the smooth piece that
// holds `inside` (a grid's cell: the gradient of a trilinear interpolant jumps at faces), and
// gradient_noise(p) the absolute rounding of its components there.
template <class F>
concept GradientField = ScalarField<F> && requires(const F& f, const Vec3& p) {
  { f.piece_gradient(p, p) } -> std::convertible_to<Vec3>;
  { f.gradient_noise(p) } -> std::convertible_to<double>;
};

// Nodes of the proxy of a switch function on an analytic field's panel (the gradient's bandwidth is
// the field's, and the panel was sized for the field).
inline constexpr int kSwitchNodes = 33;

template <GradientField F>
class FieldShading final : public EmissionWeight {
 public:
  // `local`: the ray in its own frame (lib/geometry.h, RayFrame::local), as the panels are fitted.
  // The channels of a walk ask for S once for all of them (lib/ray_accumulator.h).
  FieldShading(const F& field, const Ray& local, const Shading& shading)
      : field_(field), ray_(local), factor_(shading, local.direction) {}

  void values(double c, double d, std::span<const double> ts, std::span<double> s,
              std::span<double> noise) const override {
    compute_values(c, d, ts, s, noise);
  }

  void append_switches(double a, double b, std::vector<WeightSwitch>& out) const override {
    compute_switches(a, b, out);
  }

  double max() const override { return factor_.max(); }
  double min() const override { return factor_.min(); }

 private:
  void compute_values(double c, double d, std::span<const double> ts, std::span<double> s,
                      std::span<double> noise) const {
    const Vec3 inside = ray_.at(0.5 * (c + d));
    const ShadingFactor::Branch branch = factor_.branch(field_.piece_gradient(inside, inside));
    for (std::size_t j = 0; j < ts.size(); ++j) {
      const Vec3 g = field_.piece_gradient(ray_.at(ts[j]), inside);
      const ShadingFactor::Value v = factor_.evaluate(g, branch);
      s[j] = v.s;
      // An exactly vanishing gradient is the definition's ambient term (a constant cell, a ramp
      // without slope); a small one is a direction known only to direction_error.
      noise[j] = v.rounding + factor_.change_within(v, direction_error(g, ts[j]));
      // A piece that ends where the gradient vanishes (its switch: a one-sided normal turns there)
      // takes S's limit from inside, which the end itself cannot give (its normal is rounding).
      const bool end = ts[j] == c || ts[j] == d;
      if (end && !(g.cwiseAbs().maxCoeff() > kVanishing * field_.gradient_noise(ray_.at(ts[j]))) && d > c)
        limit_from_inside(ts[j] == c ? 1.0 : -1.0, ts[j], d - c, inside, branch, s[j], noise[j]);
    }
  }

  void compute_switches(double a, double b, std::vector<WeightSwitch>& out) const {
    if (!(b > a)) return;
    const int degree = field_.degree_along_ray();
    // A known-degree field's gradient is a polynomial of degree - 1 along a piece, so the switch
    // functions (Phong's a quadratic form in it) are of degree 2 (degree - 1) at most: exact.
    const int n = degree >= 0 ? 2 * std::max(degree - 1, 0) + 1 : kSwitchNodes;
    if (n < 2) return;  // constant: no switch inside
    const ChebyshevRule& rule = ChebyshevRule::get(n);
    const Vec3 inside = ray_.at(0.5 * (a + b));
    std::vector<Vec3> gradients(static_cast<std::size_t>(n));
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    double largest = 0;  // the gradient's largest component on the panel
    for (int j = 0; j < n; ++j) {
      gradients[j] = field_.piece_gradient(ray_.at(mid + half * rule.node(j)), inside);
      largest = std::max(largest, gradients[j].cwiseAbs().maxCoeff());
    }
    for (int k = 0; k < ShadingFactor::kSwitches; ++k) {
      if (!factor_.has_switch(k)) continue;
      panel_.a = a, panel_.b = b;
      panel_.values.resize(n);
      panel_.coefficients.resize(n);
      panel_.forget_derived();
      double size = 0;
      for (int j = 0; j < n; ++j) {
        panel_.values[j] = factor_.switch_value(k, gradients[j]);
        size = std::max(size, std::abs(panel_.values[j]));
      }
      if (!(size > 0)) continue;  // the gradient vanishes here (S = ambient): nothing switches
      rule.coefficients(panel_.values, panel_.coefficients);
      // How far the proxy's zeros can be from the function's: its own error (the tail, exact
      // degree: rounding) over the slope there.
      const double proxy_error = degree >= 0 ? 16 * n * std::numeric_limits<double>::epsilon() * size
                                             : std::max(chebyshev_accuracy(panel_.coefficients).error,
                                                        16 * n * std::numeric_limits<double>::epsilon() * size);
      crossings_.clear();
      const double zero[1] = {0.0};
      if (k == 0) append_unlocated_flips(a, b, proxy_error, out);
      if (!may_cross(panel_, zero)) continue;
      find_crossings(panel_, zero, crossings_);
      for (std::size_t i = 0; i < crossings_.size(); ++i) {
        // Two zeros of the proxy where the function itself keeps its sign between them are a
        // touch, not two switches (the proxy of a function that touches 0 dips through it): the
        // function at their middle, exactly, has the sign the proxy has before the first.
        if (i + 1 < crossings_.size()) {
          const double between = 0.5 * (crossings_[i].t + crossings_[i + 1].t);
          const double q = factor_.switch_value(k, field_.piece_gradient(ray_.at(between), inside));
          if (crossings_[i].slope != 0 && (q > 0) == (crossings_[i].slope < 0) && q != 0) {
            ++i;
            continue;
          }
        }
        const Crossing& x = crossings_[i];
        const double slope = std::abs(x.slope);
        const double dt = slope > 0 ? std::min(b - a, proxy_error / slope) : b - a;
        // S jumps at a two-sided flip, and wherever the gradient itself vanishes (a one-sided
        // normal turns there); elsewhere the terms only kink.
        const Vec3 g = field_.piece_gradient(ray_.at(x.t), inside);
        const bool jump = k == 0 || !(g.cwiseAbs().maxCoeff() > 1e-6 * largest);
        out.push_back({x.t, dt + 4 * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b)), jump});
      }
    }
  }

  // Where a two-sided normal's flips (switch 0) may lie: on each monotone part of the proxy, the
  // stretch where it is within its error of 0 (level_band) holds every zero the function has
  // there, however many (the proxy may touch 0, or cross it once where the function crosses
  // three times).  Each such stretch is charged whole as a jump, without a cut (the crossings
  // the proxy does have are cut, and charged their own dt on top).
  void append_unlocated_flips(double a, double b, double proxy_error, std::vector<WeightSwitch>& out) const {
    const double zero[1] = {0.0};
    if (!may_cross(panel_, zero, proxy_error)) return;
    breaks_.clear();
    monotone_breaks(panel_, breaks_);
    for (std::size_t i = 0; i + 1 < breaks_.size(); ++i) {
      const auto band = level_band(panel_, breaks_[i], breaks_[i + 1], 0.0, proxy_error);
      if (!band) continue;
      out.push_back({band->u, std::max(band->w - band->u, 4 * std::numeric_limits<double>::epsilon() *
                                                              std::max(std::abs(a), std::abs(b))),
                     true, false});
    }
  }

  // Below this many times its rounding the gradient's direction is not known.
  static constexpr double kVanishing = 1024;

  // The normal's direction error from the gradient's rounding: |dn| <= 2 |dg| / |g| (and never
  // more than 2, the distance between two unit vectors).
  double direction_error(const Vec3& g, double t) const {
    const double size = g.cwiseAbs().maxCoeff();
    return size > 0 ? std::min(2.0, 4 * field_.gradient_noise(ray_.at(t)) / size) : 2.0;
  }

  // S at an end t of a piece (side +1: the piece lies above t) as the linear extrapolation of S a
  // little inside, at t + side h and t + 2 side h (h = 2^-20 of the piece): S is smooth up to the
  // end on its branch, so the extrapolation is off by O(S'' h^2); the difference of the two inner
  // values (S' h) is charged on top, which covers that many times over.
  void limit_from_inside(double side, double t, double length, const Vec3& inside,
                         const ShadingFactor::Branch& branch, double& s, double& noise) const {
    const double h = std::ldexp(length, -20);
    const Vec3 g1 = field_.piece_gradient(ray_.at(t + side * h), inside);
    const Vec3 g2 = field_.piece_gradient(ray_.at(t + 2 * side * h), inside);
    const ShadingFactor::Value v1 = factor_.evaluate(g1, branch), v2 = factor_.evaluate(g2, branch);
    s = 2 * v1.s - v2.s;
    noise = 3 * (v1.rounding + factor_.change_within(v1, direction_error(g1, t + side * h))) + 2 * std::abs(v1.s - v2.s);
  }

  const F& field_;
  Ray ray_;
  ShadingFactor factor_;
  mutable RayPanel panel_;               // scratch for append_switches
  mutable std::vector<Crossing> crossings_;
  mutable std::vector<double> breaks_;     // scratch: the proxy's monotone parts
};

}  // namespace vrv
