#pragma once
// The panels a projection reference works on: the ray clipped in its own frame, cut at the
// field's structural breaks (grid cell faces), each piece one exact panel for a known-degree
// field (a ramp's line, a trilinear cell's cubic), or adaptive Chebyshev panels of an analytic
// field, halved until the proxy meets a field tolerance.  The reference integrator's own
// fit_panel and first-panel sizing (lib/reference_integrator.h), walked in ray order; its
// accumulator, and so the emission-absorption results, are untouched.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "lib/field.h"
#include "lib/geometry.h"
#include "lib/projection/projection_result.h"
#include "lib/ray_panel.h"
#include "lib/reference_integrator.h"

namespace vrv::projection_detail {

// The ray clipped to the box in its own frame; on a hit, r.hit and r's entry and exit are set.
inline std::optional<RayFrame> enter_box(const Ray& ray, const Box& box, ProjectionResult& r) {
  auto frame = clip_in_frame(ray, box);
  if (!frame) return frame;
  r.hit = true;
  r.t_entry = frame->t_entry();
  r.t_exit = frame->t_exit();
  return frame;
}

struct PanelWalk {
  long evaluations = 0;
  bool capped = false;     // a panel was accepted unresolved, or the work cap ended the walk
  bool incomplete = false;  // the walk stopped before the exit: nothing is known beyond it
};

template <ScalarField F, class Visit>
void resolve_panel(const F& field, const Ray& local, double a, double b, int level, double field_tol,
                   PanelWalk& walk, Visit& visit) {
  constexpr int max_level = 30;
  RayPanel panel = detail::fit_panel(field, local, a, b, detail::kPanelNodes, walk.evaluations);
  const ChebyshevAccuracy check = chebyshev_accuracy(panel.coefficients, panel.noise);
  const bool good = check.resolved && (check.at_rounding || panel.error <= field_tol);
  if (!good && walk.evaluations >= detail::kMaxEvaluations) {
    walk.capped = walk.incomplete = true;
    return;
  }
  const double m = 0.5 * (a + b);
  if (!good && level < max_level && m > a && m < b) {
    resolve_panel(field, local, a, m, level + 1, field_tol, walk, visit);
    if (!walk.incomplete) resolve_panel(field, local, m, b, level + 1, field_tol, walk, visit);
    return;
  }
  if (!good) walk.capped = true;
  visit(panel);
}

// visit(const RayPanel&) for every panel of [iv.t0, iv.t1] of the local ray, in order.
template <ScalarField F, class Visit>
void walk_panels(const F& field, const Ray& local, Interval iv, double field_tol, PanelWalk& walk, Visit&& visit) {
  std::vector<double> cuts{iv.t0};
  field.append_breaks(local, iv, cuts);
  cuts.push_back(iv.t1);
  std::sort(cuts.begin(), cuts.end());
  const int degree = field.degree_along_ray();
  for (std::size_t i = 0; i + 1 < cuts.size() && !walk.incomplete; ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a)) continue;
    if (walk.evaluations >= detail::kMaxEvaluations) {
      walk.capped = walk.incomplete = true;
      return;
    }
    if (degree >= 0) {
      visit(detail::fit_panel(field, local, a, b, degree + 1, walk.evaluations));
      continue;
    }
    const double tol = std::isfinite(field_tol) ? field_tol : 1.0;
    const double h0 = first_panel_length(field.bandwidth(), tol, a, b);
    const double count = first_panel_count(h0, a, b);
    if (count > 1 && h0 < 16 * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b))) {
      walk.capped = walk.incomplete = true;  // faster than positions along the ray can resolve
      return;
    }
    for (double k = 0; k < count && !walk.incomplete; ++k) {
      const double u = a + (b - a) * k / count;
      const double w = k + 1 >= count ? b : a + (b - a) * (k + 1) / count;
      resolve_panel(field, local, u, w, 0, field_tol, walk, visit);
    }
  }
}

}  // namespace vrv::projection_detail
