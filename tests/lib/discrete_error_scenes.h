#pragma once
// The scenes, rays and configurations the tests of the a-priori bound and the error estimate
// share (tests/lib/discrete_error_bound_test.cpp, discrete_error_estimate_test.cpp): smooth,
// kinked, jumping, thick and thin Marschner-Lobb, trilinear and nearest grids, a ramp.
#include <string>
#include <vector>

#include <fmt/format.h>

#include "lib/discrete_raycast.h"
#include "lib/geometry.h"
#include "studies/benchmarks/bench_rays.h"

namespace vrv::discrete_error_scenes {

inline std::string scene_text(const std::string& field, const std::string& transfer, double background = 0) {
  return fmt::format("[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\ndims = [32, 32, 32]\n[field]\n{}\n"
                     "[transfer]\n{}\n[background]\nintensity = {}\n",
                     field, transfer, background);
}

// The hard-cases study's transfer function: kinks at 0.3, 0.4, 0.5, 0.7 (scaled extinction).
inline std::string kinked(double extinction_scale) {
  return fmt::format("emission = [[0.0, 0.0], [0.3, 0.1], [0.5, 1.0], [0.7, 0.2], [1.0, 0.5]]\n"
                     "extinction = [[0.0, 0.0], [0.4, {}], [1.0, {}]]",
                     0.8 * extinction_scale, 0.3 * extinction_scale);
}
inline constexpr const char* kJump = "emission = [[0.0, 0.1], [0.45, 0.1], [0.45, 0.9], [1.0, 0.9]]\n"
                                     "extinction = [[0.0, 0.5], [0.6, 0.5], [0.6, 2.0], [1.0, 2.0]]";
inline constexpr const char* kGrid =
    "kind = \"grid\"\nresolution = [20, 20, 20]\n[field.source]\nkind = \"marschner_lobb\"";
inline constexpr const char* kNearest =
    "kind = \"grid\"\nresolution = [20, 20, 20]\ninterpolation = \"nearest\"\n[field.source]\nkind = \"marschner_lobb\"";

struct Case {
  std::string name;
  std::string text;
};

inline std::vector<Case> cases() {
  return {
      {"ml_kinked", scene_text("kind = \"marschner_lobb\"", kinked(1))},
      {"ml_thick", scene_text("kind = \"marschner_lobb\"", kinked(200))},
      {"ml_thin", scene_text("kind = \"marschner_lobb\"", kinked(1e-9), 0.25)},
      {"ml_jump", scene_text("kind = \"marschner_lobb\"", kJump, 0.5)},
      {"grid_kinked", scene_text(kGrid, kinked(1))},
      {"nearest_jump", scene_text(kNearest, kJump)},
      {"ramp_jump", scene_text("kind = \"linear_ramp\"\ngradient = [0.3, 0.2, 0.1]\noffset = 0.5", kJump)},
  };
}

inline DiscreteConfig config(SegmentRule rule, Strategy strategy, double step_or_rate) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = strategy;
  c.sampling.dims = {32, 32, 32};
  const bool by_step = strategy == Strategy::step || strategy == Strategy::vtk || strategy == Strategy::inviwo;
  (by_step ? c.sampling.step : c.sampling.rate) = step_or_rate;
  return c;
}

// Origins on a sphere of radius 3 aimed at uniform points of the box (every ray hits it): the
// benchmarks' rays.
inline std::vector<Ray> rays(int count, std::uint64_t seed) { return bench::random_rays(count, seed); }

}  // namespace vrv::discrete_error_scenes
