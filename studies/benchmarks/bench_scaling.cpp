// How time grows with image size, refinement level and grid size, and what a grid costs in
// memory: the measured points behind the scaling tables (and fitted exponents) of
// results/performance.md, which studies/benchmarks/performance_report.py writes.
//   build/bench_scaling [--benchmark_filter=...]
//
// Every render runs its pixels on all threads through the image loop (lib/image_loop.h; TBB's
// default), so the times are wall-clock (UseRealTime); `threads` records how many TBB may use.
// Camera: perspective from (0, 0, -4) at the box centre, up +y, 35 degree vertical fov, square
// images; at that fov every pixel ray meets the box [-1, 1]^3 (its front face spans +-18.4 degrees
// from 3 units away), so time per pixel is not diluted by misses (`hit_fraction` checks it).
// Scene: default_scene() (Marschner-Lobb fM = 6, alpha = 0.25 on [-1, 1]^3, emission g = f,
// extinction tau = f / 2, background 0, dims 64^3); its grids are node-layout trilinear samples of
// the same field.
//
// Series (size variable in brackets; each family's counters name it):
//   BM_Image_Reference/side    [pixels = side^2]  analytic field, reference integrator, tol 1e-10
//   BM_Image_Riemann/side      [pixels]           analytic field, riemann, entry_exit_corner,
//                                                 rate 1 over dims 64^3
//   BM_Rate_Riemann/rate       [rate]             64^3 grid, 64^2 pixels, entry_exit_corner at
//   BM_Rate_ExactLinear/rate   [rate]             `rate` samples per voxel, dims 64^3
//   BM_Grid_Riemann/n          [n]                n^3 grid, 64^2 pixels, riemann rate 1 with
//                                                 dims = n^3 (samples per ray grow with n)
//   BM_Grid_Reference/n        [n]                n^3 grid, 32^2 pixels, reference, tol 1e-10
//   BM_Grid_Build/n            [n]                make_grid (one thread): n^3 field evaluations
// Counters: pixels, side / rate / grid_n (the size), work_per_pixel (field evaluations for the
// reference, samples for the discrete rules), hit_fraction, pixels_per_s; grid_bytes = 8 n^3
// (one double per node); BM_Grid_Build also rss_bytes_per_node, the growth of the resident set
// when one grid is built (measured from /proc/self/statm, outside the timing; only where it
// grows: small grids reuse freed heap memory), and
// image_bytes_per_pixel = what `vrv render` keeps per pixel (float value, long work, double
// error estimate).
// Run time: about 40 s on 2 idle cores (each benchmark's minimum time is 0.5 s, set per
// benchmark so --benchmark_min_time does not change it; the largest cases run a fixed 1-3
// iterations).
#include <cstdio>
#include <map>
#include <memory>
#include <vector>

#include <unistd.h>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/image_loop.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"
#include "lib/scene_file.h"

namespace {

using namespace vrv;

constexpr double kTol = 1e-10;
constexpr double kMinTime = 0.5;  // per benchmark; overrides --benchmark_min_time

const Scene& scene() {
  static const Scene s = default_scene();
  return s;
}

Camera camera(int side) {
  Camera c;
  c.projection = Projection::perspective;
  c.eye = Vec3(0, 0, -4);
  c.target = Vec3(0, 0, 0);
  c.up = Vec3(0, 1, 0);
  c.fov_degrees = 35;
  c.width = c.height = side;
  validate(c);
  return c;
}

// Node-layout trilinear Marschner-Lobb grids, built once each and kept.
const GridField& grid(int n) {
  static std::map<int, std::unique_ptr<GridField>> cache;
  auto& slot = cache[n];
  if (!slot)
    slot = std::make_unique<GridField>(make_grid(scene().box, MarschnerLobb{}, {n, n, n},
                                                 GridLayout::node, Interpolation::trilinear));
  return *slot;
}

DiscreteConfig discrete_config(SegmentRule rule, double rate, int dims) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = Strategy::entry_exit_corner;
  c.sampling.rate = rate;
  c.sampling.dims = {dims, dims, dims};
  return c;
}

// Per pixel: the value (kept so the work cannot be dropped), the work and whether the ray hit.
struct PixelOut {
  double value = 0;
  long work = 0;
  bool hit = false;
};

// Renders the camera's pixels on all threads, every iteration; per_pixel(ray) -> PixelOut.
template <class PerPixel>
void render(benchmark::State& state, const Camera& cam, PerPixel&& per_pixel) {
  const long pixels = static_cast<long>(cam.width) * cam.height;
  std::vector<PixelOut> out(pixels);
  long iterations = 0;
  for (auto _ : state) {
    image_loop_into(cam, {}, per_pixel, [&](long i, const PixelOut& p) { out[i] = p; });
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    ++iterations;
  }
  long work = 0, hits = 0;
  for (const PixelOut& p : out) {
    work += p.work;
    hits += p.hit;
  }
  state.counters["pixels"] = static_cast<double>(pixels);
  state.counters["work_per_pixel"] = static_cast<double>(work) / static_cast<double>(pixels);
  state.counters["hit_fraction"] = static_cast<double>(hits) / static_cast<double>(pixels);
  state.counters["pixels_per_s"] =
      benchmark::Counter(static_cast<double>(pixels * iterations), benchmark::Counter::kIsRate);
  state.counters["threads"] = tbb::this_task_arena::max_concurrency();
}

template <class F>
void render_reference(benchmark::State& state, const F& field, const Camera& cam) {
  const Scene& s = scene();
  render(state, cam, [&](const Ray& ray) {
    const ReferenceResult r = integrate_reference(field, s.box, s.transfer, s.background, ray, {kTol});
    return PixelOut{r.value, r.evaluations, r.hit};
  });
}

template <class F>
void render_discrete(benchmark::State& state, const F& field, const Camera& cam, const DiscreteConfig& config) {
  const Scene& s = scene();
  const DiscreteRaycaster raycaster(field, s.box, s.transfer, s.background, config);
  render(state, cam, [&](const Ray& ray) {
    const DiscreteResult r = raycaster.cast(ray);
    return PixelOut{r.value, r.samples, clip(ray, s.box).has_value()};
  });
}

// ---- Image size --------------------------------------------------------------------------------

void BM_Image_Reference(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  visit_field(scene(), [&](const auto& field) { render_reference(state, field, camera(side)); });
  state.counters["side"] = side;
}

void BM_Image_Riemann(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  visit_field(scene(), [&](const auto& field) {
    render_discrete(state, field, camera(side), discrete_config(SegmentRule::riemann, 1, scene().dims[0]));
  });
  state.counters["side"] = side;
}

// ---- Refinement level --------------------------------------------------------------------------

void rate_series(benchmark::State& state, SegmentRule rule) {
  const int rate = static_cast<int>(state.range(0));
  render_discrete(state, grid(64), camera(64), discrete_config(rule, rate, 64));
  state.counters["rate"] = rate;
  state.counters["grid_n"] = 64;
}
void BM_Rate_Riemann(benchmark::State& state) { rate_series(state, SegmentRule::riemann); }
void BM_Rate_ExactLinear(benchmark::State& state) { rate_series(state, SegmentRule::exact_linear); }

// ---- Grid size ---------------------------------------------------------------------------------

void grid_counters(benchmark::State& state, int n) {
  state.counters["grid_n"] = n;
  state.counters["grid_bytes"] = static_cast<double>(sizeof(double)) * n * n * n;
}

void BM_Grid_Riemann(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  render_discrete(state, grid(n), camera(64), discrete_config(SegmentRule::riemann, 1, n));
  grid_counters(state, n);
}

void BM_Grid_Reference(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  render_reference(state, grid(n), camera(32));
  grid_counters(state, n);
}

double resident_bytes() {
  long size = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &size, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

void BM_Grid_Build(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const double nodes = static_cast<double>(n) * n * n;
  // Memory, outside the timing: the resident set with one more grid alive.
  double rss_growth = 0;
  {
    const double before = resident_bytes();
    const GridField g =
        make_grid(scene().box, MarschnerLobb{}, {n, n, n}, GridLayout::node, Interpolation::trilinear);
    rss_growth = resident_bytes() - before;
    benchmark::DoNotOptimize(g.node(0, 0, 0));
  }
  for (auto _ : state) {
    const GridField g =
        make_grid(scene().box, MarschnerLobb{}, {n, n, n}, GridLayout::node, Interpolation::trilinear);
    benchmark::DoNotOptimize(g.node(n - 1, n - 1, n - 1));
  }
  grid_counters(state, n);
  // Small grids come from heap memory freed by earlier ones (no growth to see): reported only
  // when the resident set grew, which it does for the large grids (fresh mmap'd pages).
  if (rss_growth > 0) state.counters["rss_bytes_per_node"] = rss_growth / nodes;
  state.counters["image_bytes_per_pixel"] = sizeof(float) + sizeof(long) + sizeof(double);
  state.counters["nodes_per_s"] =
      benchmark::Counter(nodes * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  using benchmark::RegisterBenchmark;
  auto rendered = [](benchmark::internal::Benchmark* b) {
    return b->UseRealTime()->Unit(benchmark::kMillisecond);
  };
  // Each point is registered on its own so that the expensive ones get a fixed iteration count.
  for (int side : {32, 64, 128, 256}) {
    auto* b = rendered(RegisterBenchmark("BM_Image_Reference", BM_Image_Reference)->Arg(side));
    if (side >= 128) b->Iterations(1);
    else b->MinTime(kMinTime);
  }
  for (int side : {32, 64, 128, 256})
    rendered(RegisterBenchmark("BM_Image_Riemann", BM_Image_Riemann)->Arg(side))->MinTime(kMinTime);
  for (int rate : {1, 2, 4, 8, 16}) {
    rendered(RegisterBenchmark("BM_Rate_Riemann", BM_Rate_Riemann)->Arg(rate))->MinTime(kMinTime);
    rendered(RegisterBenchmark("BM_Rate_ExactLinear", BM_Rate_ExactLinear)->Arg(rate))->MinTime(kMinTime);
  }
  for (int n : {16, 32, 64, 128, 256})
    rendered(RegisterBenchmark("BM_Grid_Riemann", BM_Grid_Riemann)->Arg(n))->MinTime(kMinTime);
  for (int n : {16, 32, 64, 128, 256}) {
    auto* b = rendered(RegisterBenchmark("BM_Grid_Reference", BM_Grid_Reference)->Arg(n));
    if (n >= 256) b->Iterations(1);
    else b->MinTime(kMinTime);
  }
  for (int n : {16, 32, 64, 128, 256}) {
    auto* b = RegisterBenchmark("BM_Grid_Build", BM_Grid_Build)->Arg(n)->Unit(benchmark::kMillisecond);
    if (n >= 256) b->Iterations(1);
    else if (n >= 128) b->Iterations(3);
    else b->MinTime(kMinTime);
  }

  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
