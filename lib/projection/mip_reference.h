#pragma once
// The reference maximum intensity projection along a ray: max f(s) over the clipped ray (mode
// mip), or max tau(f(s)), the transfer function's extinction of the field (mip_classified), with
// where it is first reached and an error estimate meant never to be exceeded.
//
// Candidates, never dense sampling: on every panel (projection_panels.h) its ends and the roots
// of its proxy's derivative, where the proxy is monotone in between.  A trilinear cell's cubic
// has a quadratic derivative, solved in closed form (every root, however close the pair); an
// analytic field's proxy is cut by monotone_breaks (lib/ray_panel.h), and each interior maximum
// (and minimum, classified) is refined on the field itself by Brent's safeguarded parabolic /
// golden-section search (Boost.Math) inside its monotone neighbours.  The value is the largest
// field value found (a computed value of the field, so at most its rounding above the truth); the
// truth is at most the largest proxy value plus the proxy's error, so their difference bounds the
// error.  Classified, tau is piecewise linear in v (or a monotone function of the piecewise-linear
// opacity), so its supremum over a panel is reached at the ends of the panel's value range or at
// a control value inside it: the value range of the field is all that is needed, and the crossings
// of control values give the first position.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <boost/math/tools/minima.hpp>

#include "lib/field.h"
#include "lib/geometry.h"
#include "lib/projection/projection_panels.h"
#include "lib/projection/projection_result.h"
#include "lib/ray_panel.h"
#include "lib/scene.h"
#include "lib/transfer_function.h"

namespace vrv {

namespace projection_detail {

// A place where the maximum may be: a panel's end or extremum (value: the field there), or where
// the proxy crosses a transfer function's control value (classified only; value: the level).
struct MipCandidate {
  double t = 0;
  double value = 0;
  bool crossing = false;
};

// The panel's ends and the roots of its proxy's derivative between them, in order: every root of
// a quadratic derivative (cubic cells) in closed form, else monotone_breaks.
void extremum_breaks(const RayPanel& panel, std::vector<double>& out);

class MipAccumulator {
 public:
  MipAccumulator(const TransferFunction* classify, double tol);
  double field_tolerance() const;
  bool classified() const { return tf_ != nullptr; }
  // One panel's candidates in ray order, the range of its proxy over it (exact: its values at
  // extremum_breaks) and the field error it carries.
  void add(const RayPanel& panel, std::vector<MipCandidate>& candidates, double p_min, double p_max,
           double field_error);
  struct Outcome {
    double value = 0, estimate = 0, position = 0;
    bool ambiguous = false;
    bool any = false;  // at least one panel
  };
  Outcome finish() const;

 private:
  struct Entry {
    double t = 0, q = 0, err = 0, tie = 0;
    std::size_t panel = 0;
  };
  // sup of tau over the field values [lo, hi] (tau piecewise linear, or a monotone map of it).
  double sup_over(double lo, double hi) const;
  double inf_over(double lo, double hi) const;
  const PiecewiseLinear& curve() const;
  double mapped(double y) const;  // tau from the curve's value

  const TransferFunction* tf_;
  double tol_;
  double slope_ = 1;
  std::vector<Entry> entries_;
  struct PanelBound {
    double attained = -std::numeric_limits<double>::infinity();  // sup reached by the field
    double upper = -std::numeric_limits<double>::infinity();     // bound on the true sup
    double lower = -std::numeric_limits<double>::infinity();     // the true sup is at least this
    double tie = 0;
  };
  std::vector<PanelBound> panels_;
};

// The panel's candidates: its ends (the field values the panel sampled there) and its proxy's
// extrema, the maxima (and, for a classified maximum, the minima) of an analytic field refined
// on the field itself.
template <ScalarField F>
void mip_candidates(const F& field, const Ray& local, const RayPanel& panel, bool minima, long& evaluations,
                    std::vector<double>& breaks, std::vector<MipCandidate>& out, double& p_min, double& p_max) {
  breaks.clear();
  extremum_breaks(panel, breaks);
  const std::size_t m = breaks.size();
  std::vector<double> pv(m);
  for (std::size_t i = 0; i < m; ++i) pv[i] = panel(breaks[i]);
  p_min = pv[0], p_max = pv[0];
  for (double v : pv) p_min = std::min(p_min, v), p_max = std::max(p_max, v);
  const int n = panel.size();
  const bool refine = field.degree_along_ray() < 0;
  for (std::size_t i = 0; i < m; ++i) {
    MipCandidate c{breaks[i], 0, false};
    if (i == 0 || i + 1 == m) {
      c.value = i == 0 ? panel.values[n - 1] : panel.values[0];  // Lobatto nodes hold both ends
      out.push_back(c);
      continue;
    }
    c.value = field.value(local.at(c.t));
    ++evaluations;
    const bool is_max = pv[i] >= pv[i - 1] && pv[i] >= pv[i + 1];
    const bool is_min = pv[i] <= pv[i - 1] && pv[i] <= pv[i + 1];
    if (refine && (is_max || (minima && is_min))) {
      const double sign = is_max ? 1.0 : -1.0;
      std::uintmax_t iterations = 200;
      const auto best = boost::math::tools::brent_find_minima(
          [&](double t) {
            ++evaluations;
            return -sign * field.value(local.at(t));
          },
          breaks[i - 1], breaks[i + 1], std::numeric_limits<double>::digits / 2, iterations);
      if (-sign * best.second < -sign * c.value) c.t = best.first, c.value = -sign * best.second;
    }
    out.push_back(c);
  }
}

}  // namespace projection_detail

template <ScalarField F>
ProjectionResult mip_reference(const F& field, const Box& box, const Ray& ray, const ProjectionOptions& options,
                               const TransferFunction* classify = nullptr) {
  ProjectionResult r;
  const auto frame = projection_detail::enter_box(ray, box, r);
  if (!frame) return r;
  projection_detail::MipAccumulator acc(classify, options.tol);
  const double moved = field_change_within(field, frame->position_error);
  projection_detail::PanelWalk walk;
  std::vector<double> breaks;
  std::vector<projection_detail::MipCandidate> candidates;
  std::vector<Crossing> crossings;
  const Ray& local = frame->local;
  projection_detail::walk_panels(field, local, frame->iv, acc.field_tolerance(), walk, [&](const RayPanel& panel) {
    candidates.clear();
    double p_min = 0, p_max = 0;
    projection_detail::mip_candidates(field, local, panel, classify != nullptr, walk.evaluations, breaks,
                                      candidates, p_min, p_max);
    if (classify) {
      crossings.clear();
      if (may_cross(panel, classify->breakpoints())) find_crossings(panel, classify->breakpoints(), crossings);
      for (const Crossing& x : crossings) candidates.push_back({x.t, x.level, true});
    }
    // The proxy interpolates computed values: its error, their rounding amplified at most by the
    // Lebesgue constant of up to 33 Chebyshev points (3.04 < 4), and a far origin's position error.
    acc.add(panel, candidates, p_min, p_max, panel.error + 4 * panel.noise + moved);
  });
  const auto out = acc.finish();
  r.evaluations = walk.evaluations;
  if (!out.any) {  // a chord of length 0 (a corner): the field at its one point
    const double v = field.value(local.at(frame->iv.t0));
    ++r.evaluations;
    r.value = classify ? classify->extinction(v) : v;
    r.error_estimate = 8 * std::numeric_limits<double>::epsilon() * std::abs(r.value) +
                       (classify ? 0.0 : field_value_noise(field));
    r.position = frame->t_entry();
  } else {
    r.value = out.value;
    r.error_estimate = walk.incomplete ? std::numeric_limits<double>::infinity() : out.estimate;
    r.position = frame->t_offset + out.position;
    r.ambiguous = out.ambiguous;
  }
  r.tolerance_met = !walk.capped && std::isfinite(r.value) && r.error_estimate <= options.tol;
  return r;
}

}  // namespace vrv
