// Cost of the reference integrator: field evaluations and time per ray at a tolerance.
//   build/bench_reference [--benchmark_filter=...]
// Counters: evals_per_ray (mean field evaluations), max_error_estimate.
// BM_Color_*: an RGB ray (lib/reference_channels.h) beside the same rays in grey with each of its
// channels alone and with one grey emission holding every channel's breakpoints, in one run (the
// README's RGB cost ratios: rgb over the costliest grey channel, and over the grey ray of the same
// breakpoints).
// BM_Shading_*: the same rays unshaded (0) and shaded (1: Blinn-Phong, a directional light,
// two-sided; lib/shading.h) in one run (docs/shading.md's cost ratio); BM_Color_Shaded*: shaded
// RGB rays beside each channel shaded alone.
#include <algorithm>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "studies/benchmarks/bench_rays.h"
#include "lib/reference_channels.h"
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
void run(benchmark::State& state, const F& field, const TransferFunction& tf, double tol,
         const Shading* shading = nullptr) {
  const Box box;
  const std::vector<Ray> rays = random_rays(256);
  long evaluations = 0, count = 0;
  double worst = 0;
  for (auto _ : state) {
    for (const Ray& ray : rays) {
      const ReferenceResult r = integrate_reference(field, box, tf, 0.0, ray, {tol}, shading);
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

// Three channels sharing the non-proportional extinction: red the non-proportional emission, green
// a jump, blue a ramp with kinks elsewhere; the channels' breakpoints differ.
ColorChannels color_channels() {
  const TransferFunction red = nonproportional_tf();
  const PiecewiseLinear& extinction = red.second();
  return {{red,
           TransferFunction::emission_extinction(PiecewiseLinear({{0.45, 0.1}, {0.45, 0.9}}), extinction),
           TransferFunction::emission_extinction(PiecewiseLinear({{0.2, 0}, {0.6, 0.7}, {0.9, 0.1}}), extinction)},
          {0, 0, 0}};
}

// A colour map as scene files give it (color = [[v, r, g, b], ...]): the three emissions share the
// red one's breakpoints, with their own values, over the same extinction.
ColorChannels shared_knot_channels() {
  const TransferFunction red = nonproportional_tf();
  const PiecewiseLinear& extinction = red.second();
  const auto knots = [&](double e0, double e1, double e2, double e3, double e4) {
    return TransferFunction::emission_extinction(
        PiecewiseLinear({{0, e0}, {0.3, e1}, {0.5, e2}, {0.7, e3}, {1, e4}}), extinction);
  };
  return {{red, knots(0.5, 0.2, 0.1, 0.9, 0.3), knots(0.1, 0.8, 0.4, 0.0, 1.0)}, {0, 0, 0}};
}

// The value of `f` just below v (its left limit: the lower point of a jump at v).
double left_limit(const PiecewiseLinear& f, double v) {
  const auto& p = f.points();
  const auto at = std::lower_bound(p.begin(), p.end(), v, [](const ControlPoint& c, double x) { return c.v < x; });
  return at != p.end() && at->v == v ? at->y : f(v);
}

// The grey scene with every channel's breakpoints: emission the mean of the three channels' (its
// kinks and jumps the union of theirs), the same extinction.  An RGB ray's panels must resolve all
// of these breakpoints, so this is the grey ray of the same structure as the RGB ray.
TransferFunction union_grey(const ColorChannels& color) {
  std::vector<double> knots;
  for (const TransferFunction& t : color.transfer)
    for (const ControlPoint& c : t.first().points()) knots.push_back(c.v);
  std::sort(knots.begin(), knots.end());
  knots.erase(std::unique(knots.begin(), knots.end()), knots.end());
  std::vector<ControlPoint> mean;
  for (const double v : knots) {
    double below = 0, at = 0;
    for (const TransferFunction& t : color.transfer) {
      below += left_limit(t.first(), v) / 3;
      at += t.first()(v) / 3;
    }
    if (below != at) mean.push_back({v, below});
    mean.push_back({v, at});
  }
  return TransferFunction::emission_extinction(PiecewiseLinear(std::move(mean)), color.transfer[0].second());
}

// state.range(0): 0..2 one channel alone (grey), 3 all three (RGB), 4 grey with every channel's
// breakpoints (union_grey).
template <class F>
void run_color(benchmark::State& state, const F& field, const ColorChannels& color = color_channels(),
               const Shading* shading = nullptr) {
  const Box box;
  const int channel = static_cast<int>(state.range(0));
  const TransferFunction grey_union = union_grey(color);
  const std::vector<Ray> rays = random_rays(256);
  long evaluations = 0, count = 0;
  for (auto _ : state) {
    for (const Ray& ray : rays) {
      if (channel < 3 || channel == 4) {
        const TransferFunction& tf = channel == 4 ? grey_union : color.transfer[channel];
        const ReferenceResult r = integrate_reference(field, box, tf, 0.0, ray, {1e-12}, shading);
        benchmark::DoNotOptimize(r.value);
        evaluations += r.evaluations;
      } else {
        const ChannelsReferenceResult r = integrate_color_reference(field, box, color, ray, {1e-12}, shading);
        benchmark::DoNotOptimize(r.channel[2].value);
        evaluations += r.evaluations;
      }
      ++count;
    }
  }
  state.SetLabel(channel < 3 ? fmt::format("grey channel {}", channel) : channel == 3 ? "rgb" : "grey, every channel's breakpoints");
  state.counters["evals_per_ray"] = static_cast<double>(evaluations) / count;
}

void BM_Color_MarschnerLobb(benchmark::State& state) { run_color(state, MarschnerLobb{}); }
BENCHMARK(BM_Color_MarschnerLobb)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

void BM_Color_MarschnerLobbGrid64(benchmark::State& state) {
  static const GridField grid =
      make_grid(Box{}, MarschnerLobb{}, {64, 64, 64}, GridLayout::node, Interpolation::trilinear);
  run_color(state, grid);
}
BENCHMARK(BM_Color_MarschnerLobbGrid64)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

void BM_Color_MarschnerLobbSharedKnots(benchmark::State& state) {
  run_color(state, MarschnerLobb{}, shared_knot_channels());
}
BENCHMARK(BM_Color_MarschnerLobbSharedKnots)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

void BM_Color_MarschnerLobbGrid64SharedKnots(benchmark::State& state) {
  static const GridField grid =
      make_grid(Box{}, MarschnerLobb{}, {64, 64, 64}, GridLayout::node, Interpolation::trilinear);
  run_color(state, grid, shared_knot_channels());
}
BENCHMARK(BM_Color_MarschnerLobbGrid64SharedKnots)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

Shading bench_shading() {
  Shading s;
  s.light = Vec3(0.3, -0.4, 0.87);
  return s;
}

void BM_Shading_MarschnerLobb(benchmark::State& state) {
  const Shading s = bench_shading();
  run(state, MarschnerLobb{}, nonproportional_tf(), 1e-12, state.range(0) ? &s : nullptr);
  state.SetLabel(state.range(0) ? "shaded" : "unshaded");
}
BENCHMARK(BM_Shading_MarschnerLobb)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

void BM_Shading_MarschnerLobbGrid64(benchmark::State& state) {
  static const GridField grid =
      make_grid(Box{}, MarschnerLobb{}, {64, 64, 64}, GridLayout::node, Interpolation::trilinear);
  const Shading s = bench_shading();
  run(state, grid, nonproportional_tf(), 1e-12, state.range(0) ? &s : nullptr);
  state.SetLabel(state.range(0) ? "shaded" : "unshaded");
}
BENCHMARK(BM_Shading_MarschnerLobbGrid64)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

// Shaded RGB rays (a scene file's colour map) against the same rays shaded in grey, channel by channel.
void BM_Color_ShadedMarschnerLobbSharedKnots(benchmark::State& state) {
  const Shading s = bench_shading();
  run_color(state, MarschnerLobb{}, shared_knot_channels(), &s);
}
BENCHMARK(BM_Color_ShadedMarschnerLobbSharedKnots)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

void BM_Color_ShadedMarschnerLobbGrid64SharedKnots(benchmark::State& state) {
  static const GridField grid =
      make_grid(Box{}, MarschnerLobb{}, {64, 64, 64}, GridLayout::node, Interpolation::trilinear);
  const Shading s = bench_shading();
  run_color(state, grid, shared_knot_channels(), &s);
}
BENCHMARK(BM_Color_ShadedMarschnerLobbGrid64SharedKnots)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
