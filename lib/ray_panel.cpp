#include "lib/ray_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <boost/math/tools/toms748_solve.hpp>

namespace vrv {
namespace {

// Strictly opposite signs, without the product (1e-300 times 1e-300 underflows to 0: a ramp of
// gradient 1e-300 lost its crossings' bands and was charged the whole ray).
bool opposite(double x, double y) { return (x < 0 && y > 0) || (x > 0 && y < 0); }

// Root of p(t) - v on [lo, hi] where p(lo) - v and p(hi) - v have opposite signs.
template <class F>
double bracketed_root(F&& f, double lo, double hi, double f_lo, double f_hi) {
  std::uintmax_t iterations = 100;
  const auto root = boost::math::tools::toms748_solve(
      f, lo, hi, f_lo, f_hi, boost::math::tools::eps_tolerance<double>(), iterations);
  return 0.5 * (root.first + root.second);
}

}  // namespace

// Splits [a, b] where p' changes sign, so p is monotone on every part.  A double root of p'
// that the sampling misses leaves p monotone across it, so no crossing is ever lost.
const std::vector<double>& monotone_parts_of(const RayPanel& panel) {
  std::vector<double>& breaks = panel.monotone_parts;
  if (!breaks.empty()) return breaks;
  const int n = panel.size();
  breaks.push_back(panel.a);
  if (n > 2) {
    double dc[129];
    chebyshev_derivative(panel.coefficients, {dc, static_cast<std::size_t>(n)});
    const std::span<const double> derivative{dc, static_cast<std::size_t>(n - 1)};
    const ChebyshevRule& rule = ChebyshevRule::get(std::min(2 * n + 1, 129));
    const int m = rule.size();
    // p' at every node in one multi-point pass (the nodes run from +1 down to -1; node m - 1 is -1).
    double xs[129], ds[129];
    for (int j = 0; j < m; ++j) xs[j] = rule.node(j);
    xs[m - 1] = -1;
    chebyshev_evaluate_many(derivative, {xs, static_cast<std::size_t>(m)}, {ds, static_cast<std::size_t>(m)});
    double x_prev = -1, d_prev = ds[m - 1];
    for (int j = m - 2; j >= 0; --j) {
      const double x = xs[j];
      const double d = ds[j];
      if (opposite(d_prev, d)) {
        const double root = bracketed_root(
            [&](double y) { return chebyshev_evaluate(derivative, y); }, x_prev, x, d_prev, d);
        breaks.push_back(panel.t_of(root));
      }
      if (d != 0) x_prev = x, d_prev = d;
    }
  }
  breaks.push_back(panel.b);
  return breaks;
}

void monotone_breaks(const RayPanel& panel, std::vector<double>& out) {
  const std::vector<double>& breaks = monotone_parts_of(panel);
  out.insert(out.end(), breaks.begin(), breaks.end());
}

bool may_cross(const RayPanel& panel, std::span<const double> levels, double margin) {
  if (levels.empty() || panel.coefficients.empty()) return false;
  const double c0 = panel.coefficients[0];
  double spread = 0;
  for (std::size_t k = 1; k < panel.coefficients.size(); ++k) spread += std::abs(panel.coefficients[k]);
  const double slack = 8 * static_cast<double>(panel.coefficients.size()) *
                       std::numeric_limits<double>::epsilon() * (std::abs(c0) + spread);
  const double lo = c0 - spread - slack - margin, hi = c0 + spread + slack + margin;
  if (!(lo <= hi)) return true;  // not finite: let the search decide
  const auto first = std::lower_bound(levels.begin(), levels.end(), lo);
  return first != levels.end() && *first <= hi;
}

namespace {

// Searches one level on every monotone part, appending its crossings to panel.found.
void search_level(const RayPanel& panel, double v, std::span<const double> derivative) {
  const std::vector<double>& breaks = panel.monotone_parts;
  const std::vector<double>& p = panel.found.part_values;
  const auto slope = [&](double t) { return chebyshev_evaluate(derivative, panel.x_of(t)) * 2 / (panel.b - panel.a); };
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const double lo = breaks[i], hi = breaks[i + 1];
    if (!(hi > lo)) continue;
    // Monotone here: a level strictly between the end values is crossed exactly once.
    if (std::min(p[i], p[i + 1]) < v && v < std::max(p[i], p[i + 1])) {
      const double t = bracketed_root([&](double u) { return panel(u) - v; }, lo, hi, p[i] - v, p[i + 1] - v);
      panel.found.crossings.push_back({t, v, slope(t)});
    }
    if (i > 0 && p[i] == v) panel.found.crossings.push_back({lo, v, slope(lo)});
  }
}

}  // namespace

ValueRange find_crossings(const RayPanel& panel, std::span<const double> levels,
                          std::vector<Crossing>& out) {
  RayPanel::Found& found = panel.found;
  if (found.part_values.empty())
    for (double t : monotone_parts_of(panel)) found.part_values.push_back(panel(t));
  ValueRange range{INFINITY, -INFINITY};
  for (double p : found.part_values) range.min = std::min(range.min, p), range.max = std::max(range.max, p);
  double dc[129];
  bool have_derivative = false;
  const std::size_t start = out.size();
  // A level outside the range is crossed nowhere: only those inside are looked up.
  const auto first = std::lower_bound(levels.begin(), levels.end(), range.min);
  const auto last = std::upper_bound(first, levels.end(), range.max);
  for (const double v : std::span(first, last)) {
    const auto searched = std::lower_bound(found.levels.begin(), found.levels.end(), v);
    if (searched == found.levels.end() || *searched != v) {
      if (!have_derivative) chebyshev_derivative(panel.coefficients, {dc, panel.coefficients.size()});
      have_derivative = true;
      search_level(panel, v, {dc, panel.coefficients.size()});
      found.levels.insert(searched, v);
    }
    for (const Crossing& x : found.crossings)
      if (x.level == v) out.push_back(x);
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(start), out.end(),
            [](const Crossing& x, const Crossing& y) { return x.t < y.t; });
  return range;
}

std::optional<LevelBand> level_band(const RayPanel& panel, double lo, double hi, double level,
                                    double margin) {
  if (!(hi > lo)) return std::nullopt;
  const double p_lo = panel(lo), p_hi = panel(hi);
  const bool rising = p_hi >= p_lo;
  const double p_min = rising ? p_lo : p_hi, p_max = rising ? p_hi : p_lo;
  if (p_max < level - margin || p_min > level + margin) return std::nullopt;
  // The end of the stretch on the side where p passes `target`, or the part's end.
  const auto where = [&](double target, double fallback) {
    const double f_lo = p_lo - target, f_hi = p_hi - target;
    if (!opposite(f_lo, f_hi)) return fallback;
    return bracketed_root([&](double t) { return panel(t) - target; }, lo, hi, f_lo, f_hi);
  };
  const double below = where(level - margin, rising ? lo : hi);
  const double above = where(level + margin, rising ? hi : lo);
  return LevelBand{std::min(below, above), std::max(below, above)};
}

std::optional<LevelBand> part_level_band(const RayPanel& panel, std::size_t part, double level, double margin) {
  for (const RayPanel::Found::Band& b : panel.found.bands)
    if (b.part == part && b.level == level && b.margin == margin) return b.band;
  const std::vector<double>& parts = monotone_parts_of(panel);
  const auto band = level_band(panel, parts[part], parts[part + 1], level, margin);
  panel.found.bands.push_back({part, level, margin, band});
  return band;
}

}  // namespace vrv
