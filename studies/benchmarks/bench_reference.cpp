// Cost of the reference integrator: field evaluations and time per ray at a tolerance.
//   build/bench_reference [--benchmark_filter=...]
// Counters: evals_per_ray (mean field evaluations), max_error_estimate.
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "studies/benchmarks/bench_rays.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"

namespace {

using namespace vrv;

using bench::nonproportional_tf;

TransferFunction proportional_tf() {
  return TransferFunction::emission_extinction(PiecewiseLinear({{0, 0}, {1, 1}}),
                                               PiecewiseLinear({{0, 0}, {1, 0.5}}));
}

std::vector<Ray> random_rays(int count) { return bench::random_rays(count, 7); }

template <class F>
void run(benchmark::State& state, const F& field, const TransferFunction& tf, double tol) {
  const Box box;
  const std::vector<Ray> rays = random_rays(256);
  long evaluations = 0, count = 0;
  double worst = 0;
  for (auto _ : state) {
    for (const Ray& ray : rays) {
      const ReferenceResult r = integrate_reference(field, box, tf, 0.0, ray, {tol});
      benchmark::DoNotOptimize(r.value);
      evaluations += r.evaluations;
      worst = std::max(worst, r.error_estimate);
      ++count;
    }
  }
  state.counters["evals_per_ray"] = static_cast<double>(evaluations) / count;
  state.counters["max_error_estimate"] = worst;
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(count), benchmark::Counter::kIsRate);
}

void BM_MarschnerLobb_NonProportional(benchmark::State& state) {
  run(state, MarschnerLobb{}, nonproportional_tf(), std::pow(10.0, -state.range(0)));
}
BENCHMARK(BM_MarschnerLobb_NonProportional)->Arg(6)->Arg(9)->Arg(12)->Unit(benchmark::kMillisecond);

void BM_MarschnerLobb_Proportional(benchmark::State& state) {
  run(state, MarschnerLobb{}, proportional_tf(), 1e-12);
}
BENCHMARK(BM_MarschnerLobb_Proportional)->Unit(benchmark::kMillisecond);

void BM_MarschnerLobbGrid64_NonProportional(benchmark::State& state) {
  const GridField grid = make_grid(Box{}, MarschnerLobb{}, {64, 64, 64}, GridLayout::node,
                                   Interpolation::trilinear);
  run(state, grid, nonproportional_tf(), 1e-12);
}
BENCHMARK(BM_MarschnerLobbGrid64_NonProportional)->Unit(benchmark::kMillisecond);

void BM_LinearRamp_NonProportional(benchmark::State& state) {
  run(state, LinearRamp{Vec3(0.3, 0.2, -0.1), 0.5}, nonproportional_tf(), 1e-12);
}
BENCHMARK(BM_LinearRamp_NonProportional)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
