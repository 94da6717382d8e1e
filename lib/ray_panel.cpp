#include "lib/ray_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <boost/math/tools/toms748_solve.hpp>

namespace vrv {

void find_crossings(const RayPanel& panel, std::span<const double> levels, std::vector<double>& out) {
  if (levels.empty() || panel.b <= panel.a) return;
  // Dense Chebyshev sampling: twice the proxy's degree resolves its sign pattern except for
  // near-double roots.
  const ChebyshevRule& rule = ChebyshevRule::get(std::min(2 * panel.size() + 1, 129));
  const int m = rule.size();
  double ts[129], ps[129];
  double lo = INFINITY, hi = -INFINITY;
  for (int j = 0; j < m; ++j) {
    ts[j] = panel.t_of(rule.node(m - 1 - j));  // increasing t
    ps[j] = panel(ts[j]);
    lo = std::min(lo, ps[j]);
    hi = std::max(hi, ps[j]);
  }
  ts[0] = panel.a;
  ts[m - 1] = panel.b;
  const auto first = std::lower_bound(levels.begin(), levels.end(), lo);
  const auto last = std::upper_bound(levels.begin(), levels.end(), hi);
  const std::size_t start = out.size();
  for (auto level = first; level != last; ++level) {
    const double v = *level;
    for (int j = 0; j + 1 < m; ++j) {
      const double fa = ps[j] - v, fb = ps[j + 1] - v;
      if (fa == 0) {
        if (j > 0) out.push_back(ts[j]);
        continue;
      }
      if (fa * fb >= 0) continue;
      std::uintmax_t iterations = 64;
      const auto root = boost::math::tools::toms748_solve(
          [&](double t) { return panel(t) - v; }, ts[j], ts[j + 1], fa, fb,
          boost::math::tools::eps_tolerance<double>(), iterations);
      out.push_back(0.5 * (root.first + root.second));
    }
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(start), out.end());
}

}  // namespace vrv
