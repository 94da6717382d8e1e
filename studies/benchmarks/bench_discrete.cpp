// Throughput of discrete raycasts, single thread: samples per second.
//   build/bench_discrete [--benchmark_filter=...]
// Rays: 256 random rays (origins on a sphere of radius 3 aimed into [-1, 1]^3, fixed seed),
// sampling entry_exit_corner at rate 1 over dims 64^3, transfer function g = f, tau = f / 2.
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "studies/benchmarks/bench_rays.h"
#include "lib/discrete_raycast.h"
#include "lib/scene.h"

namespace {

using namespace vrv;

std::vector<Ray> random_rays(int count) { return bench::random_rays(count, 11); }

const TransferFunction& tf() {
  static const TransferFunction t = TransferFunction::emission_extinction(
      PiecewiseLinear({{0, 0}, {1, 1}}), PiecewiseLinear({{0, 0}, {1, 0.5}}));
  return t;
}

template <class F>
void run(benchmark::State& state, const F& field, SegmentRule rule, Precision precision = Precision::double_precision) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = Strategy::entry_exit_corner;
  c.sampling.dims = {64, 64, 64};
  c.precision = precision;
  const DiscreteRaycaster raycaster(field, Box{}, tf(), 0.0, c);
  const std::vector<Ray> rays = random_rays(256);
  long samples = 0;
  for (auto _ : state)
    for (const Ray& ray : rays) {
      const DiscreteResult r = raycaster.cast(ray);
      benchmark::DoNotOptimize(r.value);
      samples += r.samples;
    }
  state.counters["samples_per_s"] = benchmark::Counter(static_cast<double>(samples), benchmark::Counter::kIsRate);
}

const GridField& grid64() {
  static const GridField g = make_grid(Box{}, MarschnerLobb{}, {64, 64, 64}, GridLayout::node, Interpolation::trilinear);
  return g;
}

void BM_Grid64_Riemann(benchmark::State& s) { run(s, grid64(), SegmentRule::riemann); }
void BM_Grid64_Alpha(benchmark::State& s) { run(s, grid64(), SegmentRule::alpha); }
void BM_Grid64_ExactLinear(benchmark::State& s) { run(s, grid64(), SegmentRule::exact_linear); }
void BM_Grid64_Riemann_Float(benchmark::State& s) { run(s, grid64(), SegmentRule::riemann, Precision::single_precision); }
void BM_Analytic_Riemann(benchmark::State& s) { run(s, MarschnerLobb{}, SegmentRule::riemann); }
void BM_Analytic_Alpha(benchmark::State& s) { run(s, MarschnerLobb{}, SegmentRule::alpha); }
void BM_Analytic_ExactLinear(benchmark::State& s) { run(s, MarschnerLobb{}, SegmentRule::exact_linear); }
BENCHMARK(BM_Grid64_Riemann);
BENCHMARK(BM_Grid64_Alpha);
BENCHMARK(BM_Grid64_ExactLinear);
BENCHMARK(BM_Grid64_Riemann_Float);
BENCHMARK(BM_Analytic_Riemann);
BENCHMARK(BM_Analytic_Alpha);
BENCHMARK(BM_Analytic_ExactLinear);

}  // namespace

BENCHMARK_MAIN();
