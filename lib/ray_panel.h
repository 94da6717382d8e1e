#pragma once
// A Chebyshev proxy of the field along one stretch [a, b] of a ray: f(t) ~ p(t).
// The reference integrator builds these front to back; every field evaluation it makes
// goes into one.  Proxies of known-degree fields (ramps, trilinear cells) are exact.
#include <optional>
#include <span>
#include <vector>

#include "lib/chebyshev.h"

namespace vrv {

struct Crossing {
  double t = 0;
  double level = 0;
  double slope = 0;  // dp/dt there: a field error df moves the crossing by df / |slope|
};

// A stretch [u, w] of a panel where p is within a margin of a level (level_band).
struct LevelBand {
  double u = 0;
  double w = 0;
};

struct RayPanel {
  double a = 0;
  double b = 0;
  std::vector<double> coefficients;  // of f on [a, b] mapped to [-1, 1]
  std::vector<double> values;        // f at the panel's own Chebyshev nodes (from +1 to -1)
  double error = 0;                  // estimated max |f - p| on [a, b]
  double noise = 0;                  // the field's own rounding level on [a, b] (absolute)
  bool resolved = true;
  // monotone_breaks' result, made on first use: a panel is asked for it by the crossings and
  // the jump bands of every channel that consumes it, and is not changed once fitted.
  mutable std::vector<double> monotone_parts{};
  // find_crossings' work, kept per level searched: an RGB ray's channels share the extinction's
  // levels, and an analytic field's panel is searched by jumps_located and again by consume.
  struct Found {
    std::vector<double> part_values;  // p at monotone_parts
    std::vector<double> levels;       // searched so far, sorted
    std::vector<Crossing> crossings;  // of those levels, grouped by level
    struct Band {
      std::size_t part = 0;
      double level = 0, margin = 0;
      std::optional<LevelBand> band;
    };
    std::vector<Band> bands;  // part_level_band's answers
  };
  mutable Found found{};

  // After new coefficients: what was derived from the old ones goes (the storage stays).
  void forget_derived() {
    monotone_parts.clear();
    found.part_values.clear();
    found.levels.clear();
    found.crossings.clear();
    found.bands.clear();
  }

  double x_of(double t) const { return (2 * t - a - b) / (b - a); }
  double t_of(double x) const { return 0.5 * (a + b) + 0.5 * (b - a) * x; }
  double operator()(double t) const { return chebyshev_evaluate(coefficients, x_of(t)); }
  int size() const { return static_cast<int>(coefficients.size()); }
};

struct ValueRange {
  double min = 0;
  double max = 0;
};
// False when no level can be crossed: none lies in c_0 +- sum_{k>=1} |c_k| (which holds every
// value of p, widened by more than Clenshaw's rounding).  find_crossings would then find none;
// skipping it saves the derivative's evaluation at 2n + 1 points.
// With `margin`, whether p comes within margin of a level.
bool may_cross(const RayPanel& panel, std::span<const double> levels, double margin = 0);
// Parameters t in (panel.a, panel.b) where p(t) crosses one of the sorted, distinct `levels`
// (transfer-function control values), sorted, appended to `out`.  The panel is first cut
// where p' changes sign; on each monotone part every level between the end values is
// crossed once and found with TOMS 748 on the proxy, so close pairs of crossings are kept.
// Each level is searched once per panel (RayPanel::found); asking again copies its crossings.
// Returns the exact range of p on the panel (its values at the monotone breaks).
ValueRange find_crossings(const RayPanel& panel, std::span<const double> levels,
                          std::vector<Crossing>& out);

// The panel's ends and the parameters where p' changes sign between them, in order: p is
// monotone between consecutive entries.  Computed once per panel and kept in it (monotone_parts).
const std::vector<double>& monotone_parts_of(const RayPanel& panel);
// The same, appended to `breaks`.
void monotone_breaks(const RayPanel& panel, std::vector<double>& breaks);

// Where p comes within `margin` of `level` on one monotone part [lo, hi] of the panel: the
// stretch [u, w] of that part on which |p - level| <= margin (one stretch, p being monotone), or
// nothing.  f = p +- margin may cross the level anywhere in it, whether or not p does: a jump's
// crossing there is known only to within the stretch.
std::optional<LevelBand> level_band(const RayPanel& panel, double lo, double hi, double level,
                                    double margin);
// level_band on the monotone part between monotone_parts[part] and [part + 1] (made), answered
// once per panel, part, level and margin (RayPanel::found: asked by jumps_located, then consume).
std::optional<LevelBand> part_level_band(const RayPanel& panel, std::size_t part, double level, double margin);

}  // namespace vrv
