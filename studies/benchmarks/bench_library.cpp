// The C++ side of studies/python/benchmark.py: reference values for a batch of rays through the
// library API (lib/vrv.h), the call `import vrv` wraps.  The rays follow a formula the Python
// script repeats bit for bit (library_rays below); the value sum lets it check they match.
#include <benchmark/benchmark.h>

#include <numeric>
#include <vector>

#include "lib/vrv.h"

namespace {

// Ray i: origin (-3, -0.8 + 1.6 a, -0.8 + 1.6 b), direction (1, 0.2 c - 0.1, 0.05) with
// a = (i mod 317) / 316, b = (i mod 331) / 330, c = (i mod 337) / 336.
std::vector<vrv::Ray> library_rays(long count) {
  std::vector<vrv::Ray> rays;
  for (long i = 0; i < count; ++i) {
    const double a = static_cast<double>(i % 317) / 316.0, b = static_cast<double>(i % 331) / 330.0,
                 c = static_cast<double>(i % 337) / 336.0;
    rays.push_back(vrv::make_ray(vrv::Vec3(-3, -0.8 + 1.6 * a, -0.8 + 1.6 * b),
                                 vrv::Vec3(1, 0.2 * c - 0.1, 0.05)));
  }
  return rays;
}

void LibraryReference(benchmark::State& state) {
  const vrv::Scene scene = vrv::default_scene();
  const std::vector<vrv::Ray> rays = library_rays(state.range(0));
  double sum = 0;
  for (auto _ : state) {
    const auto results = vrv::reference_values(scene, rays, {1e-12});
    sum = std::accumulate(results.begin(), results.end(), 0.0,
                          [](double s, const vrv::ReferenceResult& r) { return s + r.value; });
    benchmark::DoNotOptimize(sum);
  }
  state.counters["rays"] = static_cast<double>(rays.size());
  state.counters["value_sum"] = sum;
}
BENCHMARK(LibraryReference)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
