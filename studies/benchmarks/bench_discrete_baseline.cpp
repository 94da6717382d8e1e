// What the flexibility of DiscreteRaycaster costs: its throughput (field samples per second)
// against a bare hand-written trilinear-fetch-and-composite loop over exactly the same samples.
//   build/bench_discrete_baseline [--benchmark_filter=...] [--benchmark_repetitions=...]
// Goal (the issue): vrv within 2x of the bare loop, single thread and all threads.
//
// Rays and configuration as studies/benchmarks/bench_discrete.cpp: 256 random rays (origins on a
// sphere of radius 3 aimed at uniform points of [-1, 1]^3, mt19937_64 seed 11), entry_exit_corner
// sampling at rate 1 over dims = the grid resolution (64 for the analytic field), the Riemann
// rule, transfer function g = f, tau = f / 2, background 0, front to back, double precision.
//
// Fields: the analytic Marschner-Lobb field (fM = 6, alpha = 0.25) and its node-layout trilinear
// grids of 64^3 and 256^3 nodes.
//
// The baseline gets each ray's sample plan (t_first, dt, count from plan_samples) precomputed
// outside the timing, then per sample: position, an inline trilinear fetch on its own flat copy
// of the node array (or the Marschner-Lobb formula inline), g = v, tau = v / 2, and Riemann
// front-to-back compositing.  Before timing, every ray's value and sample count are compared with
// DiscreteRaycaster's (max relative difference <= 1e-12, counts equal); otherwise the benchmark
// is skipped with an error.  Both sides run over the rays with parallel_for_index, under
// ThreadLimit(1) ("1thread") or with TBB's default ("allthreads"); the rates use CPU time for one
// thread (the calling thread does all the work) and wall time for all threads.
// After the runs the program prints the slowdown vrv time / baseline time per case.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "studies/benchmarks/flat_grid.h"
#include "studies/benchmarks/bench_rays.h"
#include "studies/benchmarks/counter_recorder.h"
#include "lib/discrete_raycast.h"
#include "lib/util/parallel.h"
#include "lib/sampling.h"
#include "lib/scene.h"

namespace {

using namespace vrv;

std::vector<Ray> random_rays(int count) { return bench::random_rays(count, 11); }

const std::vector<Ray>& rays() {
  static const std::vector<Ray> r = random_rays(256);
  return r;
}

const TransferFunction& tf() {
  static const TransferFunction t = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {1, 1}}), PiecewiseLinear({{0, 0}, {1, 0.5}}));
  return t;
}

DiscreteConfig config(int dims) {
  DiscreteConfig c;
  c.rule = SegmentRule::riemann;
  c.sampling.strategy = Strategy::entry_exit_corner;
  c.sampling.rate = 1;
  c.sampling.dims = {dims, dims, dims};
  return c;
}

const GridField& grid(int n) {
  static const GridField g64 = make_grid(Box{}, MarschnerLobb{}, {64, 64, 64}, GridLayout::node, Interpolation::trilinear);
  if (n == 64) return g64;
  static const GridField g256 =
      make_grid(Box{}, MarschnerLobb{}, {256, 256, 256}, GridLayout::node, Interpolation::trilinear);
  return g256;
}

// ---- The bare loop --------------------------------------------------------------------------

// One ray as the bare loop sees it: origin, direction and its sample plan.
struct PlannedRay {
  double o[3], d[3];
  double t_first, dt;
  long count;
};

std::vector<PlannedRay> plan_rays(const std::vector<Ray>& rs, int dims) {
  const DiscreteConfig c = config(dims);
  std::vector<PlannedRay> out;
  for (const Ray& r : rs) {
    PlannedRay p{{r.origin.x(), r.origin.y(), r.origin.z()}, {r.direction.x(), r.direction.y(), r.direction.z()}, 0, 0, 0};
    if (const auto iv = clip(r, Box{})) {
      const SamplePlan plan = plan_samples(c.sampling, r, *iv, Box{});
      p.t_first = plan.t_first;
      p.dt = plan.dt;
      p.count = plan.count;
    }
    out.push_back(p);
  }
  return out;
}

using bench::FlatGrid;

// Marschner-Lobb, fM = 6, alpha = 0.25, inline.
struct InlineML {
  double fetch(double x, double y, double z) const {
    constexpr double pi = std::numbers::pi, fM = 6, alpha = 0.25;
    const double r = std::hypot(x, y);
    const double rho_r = std::cos(2 * pi * fM * std::cos(pi * r / 2));
    return (1 - std::sin(pi * z / 2) + alpha * (1 + rho_r)) / (2 * (1 + alpha));
  }
};

// Riemann front to back, g = v, tau = v / 2, background 0.
template <class Fetch>
inline double bare_ray(const Fetch& f, const PlannedRay& r) {
  double value = 0, transmittance = 1;
  const double dt = r.dt;
  for (long m = 0; m < r.count; ++m) {
    const double t = r.t_first + static_cast<double>(m) * dt;
    const double v = f.fetch(r.o[0] + t * r.d[0], r.o[1] + t * r.d[1], r.o[2] + t * r.d[2]);
    const double g = v, tau = 0.5 * v;
    value += transmittance * (g * dt);
    transmittance *= std::exp(-tau * dt);
  }
  return value;
}

// Ablation: the bare loop with one of vrv's ingredients put back at a time (grids only).
//   value       GridField::value (out of line, Vec3 position) instead of the inline fetch
//   value_tf    + TransferFunction::emission() and extinction() per sample (a branch search each)
//   value_class + instead of those, detail::Classifier::from_value as DiscreteRaycaster uses it for
//                 the Riemann rule (the TF branch cached between samples, no colour) and
//                 riemann_sample
//   plan        the bare loop (inline fetch and TF) with clip, plan_samples and the oversampled
//               recount done per ray inside the timing, as DiscreteRaycaster::cast does
enum class Impl { vrv, baseline, value, value_tf, value_class, plan };

const char* impl_name(Impl i) {
  switch (i) {
    case Impl::vrv: return "vrv";
    case Impl::baseline: return "baseline";
    case Impl::value: return "ablation_value";
    case Impl::value_tf: return "ablation_value_tf";
    case Impl::value_class: return "ablation_value_class";
    case Impl::plan: return "ablation_plan";
  }
  return "";
}

template <Impl I>
double ablation_ray(const GridField& field, const PlannedRay& r) {
  double value = 0, transmittance = 1;
  const double dt = r.dt;
  const detail::Classifier classes(tf(), dt, /*with_color=*/false);
  for (long m = 0; m < r.count; ++m) {
    const double t = r.t_first + static_cast<double>(m) * dt;
    const double v = field.value(Vec3(r.o[0] + t * r.d[0], r.o[1] + t * r.d[1], r.o[2] + t * r.d[2]));
    if constexpr (I == Impl::value) {
      const double g = v, tau = 0.5 * v;
      value += transmittance * (g * dt);
      transmittance *= std::exp(-tau * dt);
    } else if constexpr (I == Impl::value_tf) {
      const double g = tf().emission(v), tau = tf().extinction(v);
      value += transmittance * (g * dt);
      transmittance *= std::exp(-tau * dt);
    } else {
      const auto c = classes.from_value<double>(v);
      const Composite<double> e = riemann_sample(c.g, c.tau, dt);
      value += transmittance * e.emission;
      transmittance *= e.transparency;
    }
  }
  return value;
}

// One ray by one implementation (not vrv).
template <class F, class Fetch>
double bare(Impl impl, const F& field, const Fetch& fetch, const PlannedRay& r) {
  if constexpr (std::is_same_v<F, GridField>) {
    switch (impl) {
      case Impl::value: return ablation_ray<Impl::value>(field, r);
      case Impl::value_tf: return ablation_ray<Impl::value_tf>(field, r);
      case Impl::value_class: return ablation_ray<Impl::value_class>(field, r);
      default: break;
    }
  }
  return bare_ray(fetch, r);
}

// ---- Benchmarks -----------------------------------------------------------------------------

// Checks (once per field and implementation) that the bare side gives vrv's values and counts.
template <class F, class Fetch>
std::string check_same(const F& field, const Fetch& fetch, int dims, Impl impl) {
  const DiscreteRaycaster raycaster(field, Box{}, tf(), 0.0, config(dims));
  const auto planned = plan_rays(rays(), dims);
  double worst = 0;
  for (std::size_t i = 0; i < rays().size(); ++i) {
    const DiscreteResult r = raycaster.cast(rays()[i]);
    const double b = bare(impl, field, fetch, planned[i]);
    if (r.samples != planned[i].count)
      return "sample counts differ on ray " + std::to_string(i);
    const double scale = std::max(std::abs(r.value), std::abs(b));
    if (scale > 0) worst = std::max(worst, std::abs(r.value - b) / scale);
  }
  std::printf("# check dims %d, %s: max relative difference to vrv over %zu rays = %.3g\n", dims, impl_name(impl),
              rays().size(), worst);
  if (!(worst <= 1e-12)) {
    char message[96];
    std::snprintf(message, sizeof message, "%s and vrv differ: max relative difference %.3g", impl_name(impl), worst);
    return message;
  }
  return "";
}

template <class F, class Fetch>
void run(benchmark::State& state, const F& field, const Fetch& fetch, int dims, Impl impl, int threads) {
  static std::map<std::pair<const void*, Impl>, std::string> checked;  // per field and implementation
  const auto key = std::make_pair(static_cast<const void*>(&field), impl);
  if (impl != Impl::vrv && !checked.count(key)) checked[key] = check_same(field, fetch, dims, impl);
  if (impl != Impl::vrv && !checked[key].empty()) {
    state.SkipWithError(checked[key].c_str());
    return;
  }
  const ThreadLimit limit(threads);
  const DiscreteConfig cfg = config(dims);
  const DiscreteRaycaster raycaster(field, Box{}, tf(), 0.0, cfg);
  const std::vector<PlannedRay> planned = plan_rays(rays(), dims);
  const long n = static_cast<long>(rays().size());
  std::vector<double> values(n);
  std::vector<long> counts(n);
  long samples = 0;
  for (auto _ : state) {
    if (impl == Impl::vrv) {
      parallel_for_index(n, [&](long i) {
        const DiscreteResult r = raycaster.cast(rays()[i]);
        values[i] = r.value;
        counts[i] = r.samples;
      });
    } else if (impl == Impl::plan) {
      parallel_for_index(n, [&](long i) {
        const Ray& ray = rays()[i];
        PlannedRay p{{ray.origin.x(), ray.origin.y(), ray.origin.z()},
                     {ray.direction.x(), ray.direction.y(), ray.direction.z()}, 0, 0, 0};
        if (const auto iv = clip(ray, Box{})) {
          const SamplePlan fine = detail::oversampled(plan_samples(cfg.sampling, ray, *iv, Box{}), 1);
          p.t_first = fine.t_first;
          p.dt = fine.dt;
          p.count = fine.count;
        }
        values[i] = bare_ray(fetch, p);
        counts[i] = p.count;
      });
    } else if (impl == Impl::baseline) {
      parallel_for_index(n, [&](long i) {
        values[i] = bare_ray(fetch, planned[i]);
        counts[i] = planned[i].count;
      });
    } else {
      parallel_for_index(n, [&](long i) {
        values[i] = bare(impl, field, fetch, planned[i]);
        counts[i] = planned[i].count;
      });
    }
    benchmark::DoNotOptimize(values.data());
    benchmark::ClobberMemory();
    for (long c : counts) samples += c;
  }
  state.counters["samples_per_s"] = benchmark::Counter(static_cast<double>(samples), benchmark::Counter::kIsRate);
  state.counters["samples_per_iter"] = static_cast<double>(samples) / static_cast<double>(state.iterations());
}


}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  static const FlatGrid flat64(grid(64));
  const MarschnerLobb ml;
  const InlineML inline_ml;
  const struct {
    const char* name;
    int threads;
  } thread_cases[] = {{"1thread", 1}, {"allthreads", 0}};
  const char* fields[] = {"Analytic", "Grid64", "Grid256"};

  for (const char* fname : fields) {
    for (const auto& tc : thread_cases) {
      for (const Impl impl : {Impl::vrv, Impl::baseline, Impl::plan, Impl::value, Impl::value_tf, Impl::value_class}) {
        // The ablation only for the grids, single thread.
        if (impl != Impl::vrv && impl != Impl::baseline && (std::string(fname) == "Analytic" || tc.threads != 1))
          continue;
        const std::string name = std::string(fname) + "/" + impl_name(impl) + "/" + tc.name;
        const int threads = tc.threads;
        const std::string f = fname;
        auto* b = benchmark::RegisterBenchmark(name.c_str(), [=, &ml, &inline_ml](benchmark::State& s) {
          if (f == "Analytic") {
            run(s, ml, inline_ml, 64, impl, threads);
          } else if (f == "Grid64") {
            run(s, grid(64), flat64, 64, impl, threads);
          } else {
            static const FlatGrid flat256(grid(256));
            run(s, grid(256), flat256, 256, impl, threads);
          }
        });
        // One thread: CPU time (the main thread does all the work; time the scheduler gives to
        // other jobs is not counted).  All threads: wall time, the only meaningful measure.
        if (threads != 1) b->UseRealTime();
        b->Unit(benchmark::kMicrosecond)
            ->ComputeStatistics("min", [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); })
            ->ComputeStatistics("max", [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); });
      }
    }
  }

  bench::CounterRecorder recorder("samples_per_s", bench::CounterRecorder::Better::higher, false);
  benchmark::RunSpecifiedBenchmarks(&recorder);

  std::printf("\nthreads: TBB default = %u hardware threads; best = highest rate over the repetitions\n",
              std::thread::hardware_concurrency());
  std::printf("%-10s %-11s %14s %14s %16s %16s %s\n", "field", "threads", "vrv samples/s", "base samples/s",
              "vrv/base (best)", "vrv/base (median)", "(time ratio; goal <= 2)");
  for (const char* fname : fields)
    for (const auto& tc : thread_cases) {
      const std::string v = std::string(fname) + "/vrv/" + tc.name;
      const std::string b = std::string(fname) + "/baseline/" + tc.name;
      if (!recorder.has(v) || !recorder.has(b)) continue;
      const double rv = recorder.best(v), rb = recorder.best(b);
      const double ratio_median = recorder.median(b) / recorder.median(v);
      std::printf("%-10s %-11s %14.4g %14.4g %16.3f %16.3f %s\n", fname, tc.name, rv, rb, rb / rv, ratio_median,
                  rb / rv <= 2 ? "met" : "NOT met");
    }
  std::printf("\nablation, 1 thread (best repetition; time per sample, and relative to the baseline):\n");
  for (const char* fname : {"Grid64", "Grid256"}) {
    const std::string b = std::string(fname) + "/baseline/1thread";
    if (!recorder.has(b)) continue;
    const double rb = recorder.best(b);
    for (const Impl impl : {Impl::baseline, Impl::plan, Impl::value, Impl::value_tf, Impl::value_class, Impl::vrv}) {
      const std::string k = std::string(fname) + "/" + impl_name(impl) + "/1thread";
      if (!recorder.has(k)) continue;
      const double r = recorder.best(k);
      std::printf("%-10s %-22s %8.2f ns/sample %8.3f\n", fname, impl_name(impl), 1e9 / r, rb / r);
    }
  }
  benchmark::Shutdown();
  return 0;
}
