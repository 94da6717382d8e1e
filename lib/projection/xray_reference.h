#pragma once
// The reference X-ray projection along a ray: int f(s) ds over the clipped ray (mode xray), or
// int tau(f(s)) ds, the transfer function's extinction of the field (xray_classified), to an
// absolute tolerance with an error estimate meant never to be exceeded.
//
// The panels are the reference integrator's (projection_panels.h): exact polynomials on grid
// cells (cubic) and ramps (linear), adaptive Chebyshev proxies of analytic fields.  The field's
// X-ray is the proxy's integral (closed form in its coefficients); its error is the panel's length
// times (proxy error + the field's rounding + the far-origin position error).  Classified, each
// panel is cut where the proxy crosses a transfer-function control value (the crossings the
// emission-absorption reference uses), and tau(p) is integrated per piece by Clenshaw-Curtis:
// exactly with the panel's own number of points where tau is affine in v (a polynomial of the
// proxy's degree), adaptively otherwise (the opacity convention's -ln(1 - a)); the field error
// reaches it through tau's largest slope, and a jump of tau through the stretch in which the field
// may cross its level (level_band).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "lib/field.h"
#include "lib/geometry.h"
#include "lib/projection/projection_panels.h"
#include "lib/projection/projection_result.h"
#include "lib/ray_panel.h"
#include "lib/scene.h"
#include "lib/transfer_function.h"

namespace vrv {

namespace projection_detail {

// Sums the panels' integrals and their errors front to back.
class XrayAccumulator {
 public:
  // classify: nothing for the field itself, else the transfer function whose extinction is integrated.
  // end_rounding: how far the chord's computed ends may lie from the exact line's (the clip's
  // rounding): the integrand there times it, at each end, bounds what the chord's length costs.
  XrayAccumulator(const TransferFunction* classify, double tol, double length, double end_rounding);
  // The largest field error a panel may carry (its share of the tolerance).
  double field_tolerance() const;
  // moved: the field error every panel carries on top of its own (a far origin's entry point).
  void add(const RayPanel& panel, double moved);
  double value() const { return value_ + compensation_; }
  double error() const {
    return error_ + end_rounding_ * last_end_ + 2 * std::numeric_limits<double>::epsilon() * sum_abs_;
  }

 private:
  void add_piece(const RayPanel& panel, double c, double d, double field_error);
  double integrate_tau(const RayPanel& panel, double c, double d, const TransferSegment& seg, int level);
  void charge_jumps(const RayPanel& panel, double field_error);
  void accumulate(double x);
  double integrand_bound(double v) const;  // |f| or tau(v) on either side of a jump at v

  const TransferFunction* tf_;
  double tol_;
  double length_;
  double value_ = 0, compensation_ = 0, sum_abs_ = 0;
  double error_ = 0;
  double end_rounding_ = 0;
  bool first_ = true;
  double last_end_ = 0;  // the integrand's bound at the last panel's end
  std::vector<double> jump_levels_;
  std::vector<Crossing> crossings_;
  std::vector<double> breaks_;
};

}  // namespace projection_detail

template <ScalarField F>
ProjectionResult xray_reference(const F& field, const Box& box, const Ray& ray, const ProjectionOptions& options,
                                const TransferFunction* classify = nullptr) {
  ProjectionResult r;
  const auto frame = projection_detail::enter_box(ray, box, r);
  if (!frame) return r;
  const Interval iv = frame->iv;
  // clip() divides and subtracts once per slab: each end is within a few ulps of its parameter.
  const double end_rounding = 4 * std::numeric_limits<double>::epsilon() * std::max(std::abs(iv.t0), std::abs(iv.t1));
  projection_detail::XrayAccumulator acc(classify, options.tol, iv.length(), end_rounding);
  const double moved = field_change_within(field, frame->position_error);
  projection_detail::PanelWalk walk;
  projection_detail::walk_panels(field, frame->local, frame->iv, acc.field_tolerance(), walk,
                                 [&](const RayPanel& panel) { acc.add(panel, moved); });
  r.value = acc.value();
  // A walk cut short knows nothing of the rest of the ray: no finite bound.
  r.error_estimate = walk.incomplete ? std::numeric_limits<double>::infinity() : acc.error();
  r.evaluations = walk.evaluations;
  r.tolerance_met = !walk.capped && std::isfinite(r.value) && r.error_estimate <= options.tol;
  return r;
}

}  // namespace vrv
