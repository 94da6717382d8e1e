#include "studies/opacity-correction/voxel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "lib/util/task_rows.h"

namespace vrv {

GroupResult composite_group(Correction c, std::span<const double> alphas, std::span<const double> colors, int N) {
  std::vector<double> a(alphas.begin(), alphas.end()), col(colors.begin(), colors.end());
  correct_group(c, a, col, N);
  GroupResult r;
  if (c == Correction::lee_newman) r.p = lee_newman_p(alphas, alphas.empty() ? 0 : alphas[0]);
  if (c == Correction::lee_newman_quadratic) r.p = lee_newman_quadratic_p(alphas, alphas.empty() ? 0 : alphas[0]);
  // Transmittance in log space: the opacity of a dense group keeps its digits.
  double log_t = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    r.intensity += std::exp(log_t) * col[k] * a[k];
    log_t += std::log1p(-a[k]);
  }
  r.opacity = -std::expm1(log_t);
  return r;
}

FitErrorStats fit_error_stats(std::span<const double> groups, int N, double threshold) {
  FitErrorStats s;
  const long n = static_cast<long>(groups.size()) / N;
  // Each group's fit (a root of the exact p: the costly part) in parallel, the sums in order.
  struct Fit {
    double error;
    bool in_unit;
  };
  const std::vector<Fit> fits = task_values(n, [&](long i) {
    const std::span<const double> g = groups.subspan(static_cast<std::size_t>(i) * N, N);
    const double q = lee_newman_quadratic_p(g, g[0]);
    return Fit{std::fabs(q - lee_newman_p(g, g[0])), q >= 0 && q <= 1};
  });
  std::vector<double> err(static_cast<std::size_t>(n));
  for (long i = 0; i < n; ++i) {
    err[i] = fits[i].error;
    if (!fits[i].in_unit) s.all_in_unit = false;
  }
  s.groups = n;
  if (n == 0) return s;
  long above = 0;
  for (double e : err) {
    s.mean += e;
    s.max = std::max(s.max, e);
    above += e > threshold;
  }
  s.mean /= n;
  double var = 0;
  for (double e : err) var += (e - s.mean) * (e - s.mean);
  s.sd = n > 1 ? std::sqrt(var / (n - 1)) : 0;
  s.fraction_above = static_cast<double>(above) / n;
  return s;
}

std::vector<double> random_byte_groups(int N, long count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> out(static_cast<std::size_t>(count) * N);
  for (double& a : out) a = static_cast<double>(rng() >> 56) / 255.0;
  return out;
}

std::vector<double> ramp_groups(int N) {
  std::vector<double> out;
  out.reserve(256u * 256u * N);
  for (int d0 = 0; d0 < 256; ++d0)
    for (int d1 = 0; d1 < 256; ++d1)
      for (int k = 0; k < N; ++k) out.push_back((d0 + (d1 - d0) * static_cast<double>(k) / N) / 255.0);
  return out;
}

PairSurface pair_surface(Correction c) {
  PairSurface s{c, {}, {}, {}};
  s.opacity.resize(256 * 256);
  s.intensity.resize(256 * 256);
  s.p.resize(256 * 256);
  parallel_for_index(256, [&](long b) {
    for (int a = 0; a < 256; ++a) {
      const double g[2] = {a / 255.0, b / 255.0};
      const GroupResult r = composite_group(c, g, g, 2);  // colour = opacity = D / 255 (eq. 7)
      s.opacity[b * 256 + a] = r.opacity;
      s.intensity[b * 256 + a] = r.intensity;
      s.p[b * 256 + a] = r.p;
    }
  });
  return s;
}

double correction_seconds_per_sample(Correction c, std::span<const double> groups, int N, int repeats) {
  std::vector<double> scratch(groups.size());
  double best = INFINITY;
  volatile double sink = 0;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    std::copy(groups.begin(), groups.end(), scratch.begin());
    for (std::size_t i = 0; i + N <= scratch.size(); i += N)
      correct_group(c, std::span<double>(scratch.data() + i, N), std::span<double>(), N);
    const auto t1 = std::chrono::steady_clock::now();
    sink = sink + scratch[scratch.size() / 2];
    best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
  }
  return groups.empty() ? 0 : best / static_cast<double>(groups.size());
}

}  // namespace vrv
