// The opacity corrections' own cost per sample, and their share of a whole oversampled raycast:
// an answer to Lee & Newman's (WSCG 2007) Table 1 on today's hardware.  The paper reports, for
// 5x oversampling over 40 datasets, that its quadratic-fit correction is 12.36x faster than
// Lacroute/Lichtenbelt's for the correction alone and 1.85x faster for the whole raycast
// (averages; no lookup tables on either side).
//   build/bench_corrections [--benchmark_filter=...] [--benchmark_repetitions=...]
//
// Correction only (BM_Correct/<variant>/N): 4096 groups of N random 8-bit opacities
// (alpha = k / 255, k uniform in 0..255, mt19937_64 seed 5), per unit step as in the renderer's
// convention.  One iteration corrects every group into an output array.  Variants:
//   copy            out = alpha (the loop and memory traffic alone, a floor)
//   lacroute_pow    out = 1 - pow(1 - alpha, 1.0 / N)            (the textbook formula, eq. 5)
//   lacroute_vrv    vrv::correct_group(lacroute): -expm1(log1p(-alpha) / N), clamped, N checked
//   lacroute_lut    out = table[k], 256 entries per N (exact here: the input is 8-bit)
//   lee_newman_vrv  vrv::correct_group(lee_newman): p solved exactly (TOMS 748), out = p alpha
//   quadratic_vrv   vrv::correct_group(lee_newman_quadratic): the paper's fit, vrv's edge cases
//   quadratic_lean  the paper's fit written inline without vrv's edge handling (M^-1 closed
//                   form, F at 0, 1/2, 1 as products, the root in [0, 1]) - what a paper's
//                   implementation would cost
//   quadratic_lut   N = 2 only: p tabulated over (k0, k1), 65536 entries; for N = 5 the table
//                   would need 256^5 = 1.1e12 entries, so it is not meaningful
// ns_per_sample = CPU time per iteration / (4096 N).
//
// Whole raycast (BM_Raycast/<correction>/N): DiscreteRaycaster on the 64^3 node-layout
// trilinear Marschner-Lobb grid, the 256 random rays of bench_discrete.cpp (seed 11),
// entry_exit_corner at rate 1 over dims 64, rule alpha, oversample N (5 or 2), transfer
// function g = f, tau = f / 2, single thread.  ns_per_sample = CPU time / field samples.
// After the runs the program prints the ratios matching Table 1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "studies/benchmarks/flat_grid.h"
#include "studies/benchmarks/bench_rays.h"
#include "studies/benchmarks/counter_recorder.h"
#include "lib/discrete_raycast.h"
#include "lib/opacity_correction.h"
#include "lib/scene.h"

namespace {

using namespace vrv;

constexpr int kGroups = 4096;

struct Groups {
  int N;
  std::vector<std::uint8_t> code;  // kGroups * N
  std::vector<double> alpha;       // code / 255
};

const Groups& groups(int N) {
  static std::map<int, Groups> cache;
  auto it = cache.find(N);
  if (it != cache.end()) return it->second;
  Groups g{N, {}, {}};
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> k(0, 255);
  for (int i = 0; i < kGroups * N; ++i) {
    g.code.push_back(static_cast<std::uint8_t>(k(rng)));
    g.alpha.push_back(g.code.back() / 255.0);
  }
  return cache.emplace(N, std::move(g)).first->second;
}

// The paper's quadratic fit, inline: F(p) = prod (1 - p a_k) - (1 - a_0) at p = 0, 1/2, 1;
// F^(p) = A p^2 + B p + C through them (M^-1 for 0, 1/2, 1 in closed form:
// A = 2 F0 - 4 Fh + 2 F1, B = -3 F0 + 4 Fh - F1, C = F0); the root of F^ in [0, 1].  Two guards
// keep it to the same answers as vrv's (alpha_0 = 0 -> p = 0; F(1) >= 0 -> p = 1).
inline double lean_quadratic_p(const double* a, int N) {
  if (a[0] == 0) return 0;  // a transparent unit sample: only p = 0 keeps the group transparent
  const double target = 1 - a[0];
  double ph = 1, p1 = 1;
  for (int k = 0; k < N; ++k) {
    ph *= 1 - 0.5 * a[k];
    p1 *= 1 - a[k];
  }
  const double F0 = 1 - target, Fh = ph - target, F1 = p1 - target;
  if (F1 >= 0) return 1;  // even p = 1 is not too opaque (an opaque unit sample, or the rest zero)
  const double A = 2 * F0 - 4 * Fh + 2 * F1, B = -3 * F0 + 4 * Fh - F1, C = F0;
  double p;
  if (A == 0) {
    p = B != 0 ? -C / B : 1.0;
  } else {
    const double disc = std::max(0.0, B * B - 4 * A * C);
    const double s = std::sqrt(disc);
    const double r1 = (-B - s) / (2 * A), r2 = (-B + s) / (2 * A);
    p = (r1 >= 0 && r1 <= 1) ? r1 : r2;
  }
  return std::clamp(p, 0.0, 1.0);
}

enum class Variant {
  copy,
  lacroute_pow,
  lacroute_vrv,
  lacroute_lut,
  lee_newman_vrv,
  quadratic_vrv,
  quadratic_lean,
  quadratic_lut
};

void BM_Correct(benchmark::State& state, Variant v) {
  const int N = static_cast<int>(state.range(0));
  const Groups& g = groups(N);
  const std::size_t n = g.alpha.size();
  std::vector<double> out(n);

  std::vector<double> table;  // lacroute_lut: alpha'(k); quadratic_lut: p(k0, k1)
  if (v == Variant::lacroute_lut) {
    for (int k = 0; k < 256; ++k) table.push_back(lacroute(k / 255.0, N));
  } else if (v == Variant::quadratic_lut) {
    if (N != 2) {
      state.SkipWithError("a quadratic lookup table needs 256^N entries: only N = 2 is meaningful");
      return;
    }
    table.resize(256 * 256);
    for (int k1 = 0; k1 < 256; ++k1)
      for (int k0 = 0; k0 < 256; ++k0) {
        const double a[2] = {k0 / 255.0, k1 / 255.0};
        table[k1 * 256 + k0] = lee_newman_quadratic_p(a, a[0]);
      }
  }
  const double inv_N = 1.0 / N;
  const double* a = g.alpha.data();
  const std::uint8_t* code = g.code.data();

  for (auto _ : state) {
    switch (v) {
      case Variant::copy:
        std::copy(a, a + n, out.begin());
        break;
      case Variant::lacroute_pow:
        for (std::size_t i = 0; i < n; ++i) out[i] = 1 - std::pow(1 - a[i], inv_N);
        break;
      case Variant::lacroute_lut:
        for (std::size_t i = 0; i < n; ++i) out[i] = table[code[i]];
        break;
      case Variant::lacroute_vrv:
      case Variant::lee_newman_vrv:
      case Variant::quadratic_vrv: {
        const Correction c = v == Variant::lacroute_vrv     ? Correction::lacroute
                             : v == Variant::lee_newman_vrv ? Correction::lee_newman
                                                            : Correction::lee_newman_quadratic;
        std::copy(a, a + n, out.begin());
        for (std::size_t i = 0; i < n; i += N)
          correct_group(c, std::span<double>(out.data() + i, N), std::span<double>(), N);
        break;
      }
      case Variant::quadratic_lean:
        for (std::size_t i = 0; i < n; i += N) {
          const double p = lean_quadratic_p(a + i, N);
          for (int k = 0; k < N; ++k) out[i + k] = p * a[i + k];
        }
        break;
      case Variant::quadratic_lut:
        for (std::size_t i = 0; i < n; i += 2) {
          const double p = table[code[i + 1] * 256 + code[i]];
          out[i] = p * a[i];
          out[i + 1] = p * a[i + 1];
        }
        break;
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  // Counter(x * 1e-9, rate | invert) = time / (x * 1e-9) = nanoseconds per unit of x.
  state.counters["ns_per_sample"] = benchmark::Counter(
      1e-9 * static_cast<double>(n) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// ---- Whole raycast --------------------------------------------------------------------------

std::vector<Ray> random_rays(int count) { return bench::random_rays(count, 11); }

const TransferFunction& tf() {
  static const TransferFunction t = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {1, 1}}), PiecewiseLinear({{0, 0}, {1, 0.5}}));
  return t;
}

const GridField& grid64() {
  static const GridField g = make_grid(Box{}, MarschnerLobb{}, {64, 64, 64}, GridLayout::node, Interpolation::trilinear);
  return g;
}

void BM_Raycast(benchmark::State& state, Correction correction) {
  DiscreteConfig c;
  c.rule = SegmentRule::alpha;
  c.sampling.strategy = Strategy::entry_exit_corner;
  c.sampling.rate = 1;
  c.sampling.dims = {64, 64, 64};
  c.oversample = static_cast<int>(state.range(0));
  c.correction = correction;
  const DiscreteRaycaster raycaster(grid64(), Box{}, tf(), 0.0, c);
  static const std::vector<Ray> rays = random_rays(256);
  long samples = 0;
  for (auto _ : state)
    for (const Ray& ray : rays) {
      const DiscreteResult r = raycaster.cast(ray);
      benchmark::DoNotOptimize(r.value);
      samples += r.samples;
    }
  state.counters["ns_per_sample"] =
      benchmark::Counter(1e-9 * static_cast<double>(samples), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["samples_per_iter"] = static_cast<double>(samples) / static_cast<double>(state.iterations());
}

// ---- Whole raycast, bare ----------------------------------------------------------------------
// The same oversampled alpha-rule raycast written as a lean renderer would (the paper's setting:
// the correction then is a large part of the work): each ray's fine plan precomputed, an inline
// trilinear fetch on a flat copy of the 64^3 nodes, alpha_unit = -expm1(-tau * unit_step) and
// colour g / tau as vrv classifies (tau = v / 2, g = v), groups of N, a pluggable correction, front
// to back.  With vrv's corrections (correct_group) the values equal DiscreteRaycaster's (checked
// outside timing, else the benchmark is skipped); pow, lean and lut are other arithmetic.

struct FinePlan {
  double o[3], d[3];
  double t_first, dx, unit_step;
  long count;
};

using bench::FlatGrid;

enum class BareCorrection { none, lacroute_pow, lacroute_vrv, lacroute_lut8, lee_newman_vrv, quadratic_vrv, quadratic_lean };

const FlatGrid& flat64() {
  static const FlatGrid f(grid64());
  return f;
}

std::vector<FinePlan> fine_plans(const std::vector<Ray>& rays, int N) {
  SamplingConfig sc;
  sc.strategy = Strategy::entry_exit_corner;
  sc.rate = 1;
  sc.dims = {64, 64, 64};
  std::vector<FinePlan> out;
  for (const Ray& r : rays) {
    FinePlan f{{r.origin.x(), r.origin.y(), r.origin.z()}, {r.direction.x(), r.direction.y(), r.direction.z()}, 0, 0, 0, 0};
    if (const auto iv = clip(r, Box{})) {
      const SamplePlan plan = plan_samples(sc, r, *iv, Box{});
      const SamplePlan fine = detail::oversampled(plan, N);
      f.t_first = fine.t_first;
      f.dx = fine.dt;
      f.unit_step = plan.dt;
      f.count = fine.count;
    }
    out.push_back(f);
  }
  return out;
}

double bare_alpha_ray(const FinePlan& r, int N, BareCorrection bc, const std::vector<double>& lut, double* alphas,
                      double* colors) {
  const FlatGrid& g = flat64();
  const double inv_N = 1.0 / N;
  double value = 0, transmittance = 1;
  for (long m0 = 0; m0 < r.count; m0 += N) {
    const long n = std::min<long>(N, r.count - m0);
    for (long j = 0; j < n; ++j) {
      const double t = r.t_first + static_cast<double>(m0 + j) * r.dx;
      const double v = g.fetch(r.o[0] + t * r.d[0], r.o[1] + t * r.d[1], r.o[2] + t * r.d[2]);
      const double gv = v, tau = 0.5 * v;
      alphas[j] = -std::expm1(-tau * r.unit_step);
      colors[j] = tau > 0 ? gv / tau : 0.0;
    }
    switch (bc) {
      case BareCorrection::none:
        break;
      case BareCorrection::lacroute_pow:
        for (long j = 0; j < n; ++j) alphas[j] = 1 - std::pow(1 - alphas[j], inv_N);
        break;
      case BareCorrection::lacroute_lut8:  // the opacity quantised to 8 bits, as a table renderer would
        for (long j = 0; j < n; ++j) alphas[j] = lut[static_cast<int>(alphas[j] * 255 + 0.5)];
        break;
      case BareCorrection::lacroute_vrv:
        correct_group(Correction::lacroute, std::span(alphas, n), std::span(colors, n), N);
        break;
      case BareCorrection::lee_newman_vrv:
        correct_group(Correction::lee_newman, std::span(alphas, n), std::span(colors, n), N);
        break;
      case BareCorrection::quadratic_vrv:
        correct_group(Correction::lee_newman_quadratic, std::span(alphas, n), std::span(colors, n), N);
        break;
      case BareCorrection::quadratic_lean: {  // target 1 - alpha_0 also for a partial last group
        const double p = lean_quadratic_p(alphas, static_cast<int>(n));
        for (long j = 0; j < n; ++j) alphas[j] *= p;
        break;
      }
    }
    for (long j = 0; j < n; ++j) {
      value += transmittance * (colors[j] * alphas[j]);
      transmittance *= 1 - alphas[j];
    }
  }
  return value;  // background 0
}

void BM_BareRaycast(benchmark::State& state, BareCorrection bc) {
  const int N = static_cast<int>(state.range(0));
  static const std::vector<Ray> rays = random_rays(256);
  const std::vector<FinePlan> plans = fine_plans(rays, N);
  std::vector<double> lut;
  for (int k = 0; k < 256; ++k) lut.push_back(lacroute(k / 255.0, N));
  std::vector<double> alphas(N), colors(N);

  // Same work as DiscreteRaycaster for vrv's corrections.
  const Correction vc = bc == BareCorrection::lacroute_vrv     ? Correction::lacroute
                        : bc == BareCorrection::lee_newman_vrv ? Correction::lee_newman
                        : bc == BareCorrection::quadratic_vrv  ? Correction::lee_newman_quadratic
                                                               : Correction::none;
  if (bc == BareCorrection::none || vc != Correction::none) {
    DiscreteConfig c;
    c.rule = SegmentRule::alpha;
    c.sampling.strategy = Strategy::entry_exit_corner;
    c.sampling.rate = 1;
    c.sampling.dims = {64, 64, 64};
    c.oversample = N;
    c.correction = vc;
    const DiscreteRaycaster raycaster(grid64(), Box{}, tf(), 0.0, c);
    double worst = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const DiscreteResult r = raycaster.cast(rays[i]);
      const double b = bare_alpha_ray(plans[i], N, bc, lut, alphas.data(), colors.data());
      if (r.samples != plans[i].count) {
        state.SkipWithError("sample counts differ");
        return;
      }
      const double scale = std::max(std::abs(r.value), std::abs(b));
      if (scale > 0) worst = std::max(worst, std::abs(r.value - b) / scale);
    }
    if (!(worst <= 1e-12)) {
      char message[96];
      std::snprintf(message, sizeof message, "bare raycast differs from DiscreteRaycaster: %.3g", worst);
      state.SkipWithError(message);
      return;
    }
  }

  long samples = 0;
  for (auto _ : state)
    for (const FinePlan& p : plans) {
      benchmark::DoNotOptimize(bare_alpha_ray(p, N, bc, lut, alphas.data(), colors.data()));
      samples += p.count;
    }
  state.counters["ns_per_sample"] =
      benchmark::Counter(1e-9 * static_cast<double>(samples), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["samples_per_iter"] = static_cast<double>(samples) / static_cast<double>(state.iterations());
}


benchmark::internal::Benchmark* with_min(benchmark::internal::Benchmark* b) {
  return b->ComputeStatistics("min", [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); });
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  const std::pair<const char*, Variant> variants[] = {
      {"copy", Variant::copy},
      {"lacroute_pow", Variant::lacroute_pow},
      {"lacroute_vrv", Variant::lacroute_vrv},
      {"lacroute_lut", Variant::lacroute_lut},
      {"lee_newman_vrv", Variant::lee_newman_vrv},
      {"quadratic_vrv", Variant::quadratic_vrv},
      {"quadratic_lean", Variant::quadratic_lean},
      {"quadratic_lut", Variant::quadratic_lut},
  };
  for (const auto& [name, v] : variants) {
    auto* b = with_min(benchmark::RegisterBenchmark((std::string("BM_Correct/") + name).c_str(), BM_Correct, v));
    if (v == Variant::quadratic_lut) b->Arg(2);
    else b->Arg(5)->Arg(2);
  }
  const std::pair<const char*, Correction> corrections[] = {
      {"none", Correction::none},
      {"lacroute", Correction::lacroute},
      {"lee_newman_quadratic", Correction::lee_newman_quadratic},
      {"lee_newman", Correction::lee_newman},
  };
  for (const auto& [name, c] : corrections)
    with_min(benchmark::RegisterBenchmark((std::string("BM_Raycast/") + name).c_str(), BM_Raycast, c))
        ->Arg(5)->Arg(2)->Unit(benchmark::kMicrosecond);

  // The lean fit against vrv's on the benchmark's groups (outside timing).
  for (const int N : {5, 2}) {
    const Groups& g = groups(N);
    double worst = 0;
    int differ = 0;
    for (int i = 0; i < kGroups; ++i) {
      const double* a = g.alpha.data() + static_cast<std::size_t>(i) * N;
      const double d = std::abs(lean_quadratic_p(a, N) - lee_newman_quadratic_p(std::span(a, N), a[0]));
      worst = std::max(worst, d);
      differ += d > 1e-9;
    }
    std::printf("# N = %d: quadratic_lean vs vrv's quadratic p: max |diff| %.3g, %d of %d groups differ by > 1e-9\n", N,
                worst, differ, kGroups);
  }

  const std::pair<const char*, BareCorrection> bare[] = {
      {"none", BareCorrection::none},
      {"lacroute_pow", BareCorrection::lacroute_pow},
      {"lacroute_vrv", BareCorrection::lacroute_vrv},
      {"lacroute_lut8", BareCorrection::lacroute_lut8},
      {"lee_newman_vrv", BareCorrection::lee_newman_vrv},
      {"quadratic_vrv", BareCorrection::quadratic_vrv},
      {"quadratic_lean", BareCorrection::quadratic_lean},
  };
  for (const auto& [name, c] : bare)
    with_min(benchmark::RegisterBenchmark((std::string("BM_BareRaycast/") + name).c_str(), BM_BareRaycast, c))
        ->Arg(5)->Arg(2)->Unit(benchmark::kMicrosecond);

  bench::CounterRecorder rec("ns_per_sample", bench::CounterRecorder::Better::lower, true);
  benchmark::RunSpecifiedBenchmarks(&rec);

  for (const int N : {5, 2}) {
    std::string n = "/";
    n += std::to_string(N);  // (not "/" + ...: GCC 12 warns falsely, -Wrestrict)
    auto C = [&](const char* v) { return rec.best(std::string("BM_Correct/") + v + n); };
    auto R = [&](const char* v) { return rec.best(std::string("BM_Raycast/") + v + n); };
    auto Cm = [&](const char* v) { return rec.median(std::string("BM_Correct/") + v + n); };
    auto Rm = [&](const char* v) { return rec.median(std::string("BM_Raycast/") + v + n); };
    auto Bm = [&](const char* v) { return rec.median(std::string("BM_BareRaycast/") + v + n); };
    std::printf("\nN = %d, correction only (best repetition, ns per sample; ratio = variant / quadratic variant)\n", N);
    std::printf("  %-36s %8s %8s %8s %8s\n", "", "ns", "/q_vrv", "/q_lean", "/q_lut");
    for (const char* v : {"lacroute_pow", "lacroute_vrv", "lacroute_lut", "lee_newman_vrv", "quadratic_vrv",
                          "quadratic_lean", "quadratic_lut", "copy"})
      std::printf("  %-36s %8.3f %8.3f %8.3f %8.3f\n", v, C(v), C(v) / C("quadratic_vrv"), C(v) / C("quadratic_lean"),
                  C(v) / C("quadratic_lut"));
    std::printf("  paper Table 1 (N = 5, average): Lacroute / quadratic = 12.36 (range 6.79-14.72)\n");
    std::printf("N = %d, whole raycast (ns per field sample)\n", N);
    for (const char* v : {"none", "lacroute", "lee_newman_quadratic", "lee_newman"})
      std::printf("  %-36s %8.3f  (correction share %.3f ns)\n", v, R(v), R(v) - R("none"));
    std::printf("  lacroute / lee_newman_quadratic     = %.3f   (paper, N = 5: 1.85, range 1.77-2.00)\n",
                R("lacroute") / R("lee_newman_quadratic"));
    std::printf("  lacroute / lee_newman (exact)        = %.3f\n", R("lacroute") / R("lee_newman"));
    auto B = [&](const char* v) { return rec.best(std::string("BM_BareRaycast/") + v + n); };
    std::printf("N = %d, bare raycast (ns per field sample)\n", N);
    for (const char* v : {"none", "lacroute_pow", "lacroute_vrv", "lacroute_lut8", "lee_newman_vrv", "quadratic_vrv",
                          "quadratic_lean"})
      std::printf("  %-36s %8.3f  (correction share %.3f ns)\n", v, B(v), B(v) - B("none"));
    std::printf("  lacroute_pow / quadratic_lean       = %.3f   (the paper's pair, as far as it says)\n",
                B("lacroute_pow") / B("quadratic_lean"));
    std::printf("  lacroute_vrv / quadratic_vrv        = %.3f\n", B("lacroute_vrv") / B("quadratic_vrv"));
    std::printf("  lacroute_pow / quadratic_vrv        = %.3f\n", B("lacroute_pow") / B("quadratic_vrv"));
    std::printf("  lacroute_lut8 / quadratic_lean      = %.3f\n", B("lacroute_lut8") / B("quadratic_lean"));
    std::printf("N = %d, the Table 1 ratios from the medians instead: correction lacroute_pow / quadratic_lean %.3f,"
                " lacroute_vrv / quadratic_vrv %.3f; raycast lacroute / lee_newman_quadratic %.3f; bare raycast"
                " lacroute_pow / quadratic_lean %.3f\n",
                N, Cm("lacroute_pow") / Cm("quadratic_lean"), Cm("lacroute_vrv") / Cm("quadratic_vrv"),
                Rm("lacroute") / Rm("lee_newman_quadratic"), Bm("lacroute_pow") / Bm("quadratic_lean"));
  }
  benchmark::Shutdown();
  return 0;
}
