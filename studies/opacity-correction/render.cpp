#include "studies/opacity-correction/render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "lib/image_loop.h"
#include "lib/util/parallel.h"
#include "lib/vrv.h"
#include "lib/util/progress.h"
#include "lib/reference_integrator.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/reference_audit.h"

namespace vrv {

DiscreteConfig oversampled_config(Correction c, int N, double unit_step, bool centred) {
  DiscreteConfig config;
  config.rule = SegmentRule::alpha;
  config.sampling.strategy = Strategy::step;
  config.sampling.step = unit_step;
  config.oversample = N;
  config.correction = c;
  config.centred_oversamples = centred;
  return config;
}

RenderValues render_values(const RenderScenes& s, const Camera& camera, const std::vector<RenderMethod>& methods,
                           bool progress, Checkpoints* checkpoints, ReferenceAudit& audit) {
  const long pixels = static_cast<long>(camera.width) * camera.height;
  RenderValues out;
  out.reference.assign(pixels, 0);
  out.methods.assign(methods.size(), std::vector<double>(pixels, 0));
  std::vector<DiscreteConfig> configs;
  for (const RenderMethod& m : methods) configs.push_back(oversampled_config(m.correction, m.N, s.unit_step, m.centred));
  // Per pixel: the reference, its estimate, each method's value; one image row is one checkpoint.
  const std::size_t width = 2 + configs.size();
  Progress bar("render", pixels, progress);
  ImageLoopHooks hooks;
  hooks.block = camera.width;
  hooks.progress = [&](long done) { bar.advance(done); };
  const std::vector<double> v = image_records(camera, {}, width, [&](const Ray& ray, std::span<double> o) {
    const ReferenceResult ref = audited_reference(audit, s.analytic, ray, {s.reference_tol});
    o[0] = ref.value;
    o[1] = ref.error_estimate;
    for (std::size_t k = 0; k < configs.size(); ++k) o[2 + k] = discrete_raycast(s.sampled, ray, configs[k]).value;
  }, hooks, checkpoint_blocks(checkpoints, "render"));
  bar.finish();
  for (long i = 0; i < pixels; ++i) {
    const double* o = v.data() + static_cast<std::size_t>(i) * width;
    out.reference[i] = o[0];
    out.worst_estimate = std::max(out.worst_estimate, o[1]);
    for (std::size_t k = 0; k < configs.size(); ++k) out.methods[k][i] = o[2 + k];
  }
  return out;
}

Image to_image(const std::vector<double>& values, int width, int height) {
  Image image(width, height);
  for (std::size_t i = 0; i < values.size(); ++i) image.pixels[i] = static_cast<float>(values[i]);
  return image;
}

ErrorStats pixel_difference(const std::vector<double>& a, const std::vector<double>& b) {
  ErrorSums sums;
  for (std::size_t i = 0; i < a.size(); ++i) sums.add(a[i] - b[i]);
  return sums.stats();
}

std::vector<double> render_groups(const RenderScenes& s, const Camera& camera, int N, bool centred) {
  const DiscreteConfig config = oversampled_config(Correction::none, N, s.unit_step, centred);
  const GridField& grid = std::get<GridField>(s.sampled.field);
  const PiecewiseLinear& opacity = s.sampled.transfer.first();
  const std::vector<std::vector<double>> per_pixel = image_loop(camera, [&](const Ray& ray) {
    std::vector<double> groups;
    const auto iv = clip(ray, s.sampled.box);
    if (!iv) return groups;
    // The raycaster's own fine plan (lib/discrete_raycast_impl.h), so the groups are its groups.
    const SamplePlan fine = detail::oversampled(plan_samples(config.sampling, ray, *iv, s.sampled.box), N, centred);
    for (long m0 = 0; m0 + N <= fine.count; m0 += N)
      for (long j = 0; j < N; ++j) groups.push_back(std::clamp(opacity(grid.value(ray.at(fine.t(m0 + j)))), 0.0, 1.0));
    return groups;
  });
  std::vector<double> out;
  for (const auto& g : per_pixel) out.insert(out.end(), g.begin(), g.end());
  return out;
}

std::vector<SweepRow> error_against_N(const RenderScenes& s, const std::vector<Ray>& rays,
                                      const std::vector<Correction>& corrections, const std::vector<int>& Ns,
                                      bool centred, bool progress, Checkpoints* checkpoints, ReferenceAudit& audit) {
  const long R = static_cast<long>(rays.size());
  constexpr long kBlock = 64;  // rays per checkpoint
  const std::string key = centred ? "sweep_centred" : "sweep_first";
  Progress bar("N sweep", R * static_cast<long>(1 + corrections.size() * Ns.size()), progress);
  const std::vector<double> reference = checkpointed_items(checkpoints, key + "_reference", R, kBlock, 1,
                                                           [&](long i, std::span<double> o) {
    o[0] = audited_reference(audit, s.analytic, rays[i], {s.reference_tol}).value;
  }, [&](long done) { bar.advance(done); });
  std::vector<SweepRow> rows;
  for (int N : Ns) {
    // Per ray: correction none first (for the differences), then each correction.
    const std::size_t width = 1 + corrections.size();
    const std::vector<double> v = checkpointed_items(checkpoints, fmt::format("{}_N{}", key, N), R, kBlock, width,
                                                     [&](long i, std::span<double> o) {
      o[0] = discrete_raycast(s.analytic, rays[i], oversampled_config(Correction::none, N, s.unit_step, centred)).value;
      for (std::size_t c = 0; c < corrections.size(); ++c)
        o[1 + c] = discrete_raycast(s.analytic, rays[i], oversampled_config(corrections[c], N, s.unit_step, centred)).value;
    }, [&](long done) { bar.advance(done * static_cast<long>(corrections.size())); });
    std::vector<std::vector<double>> values(corrections.size(), std::vector<double>(R));  // values[c][ray]
    std::vector<double> none(R);
    for (long i = 0; i < R; ++i) {
      none[i] = v[static_cast<std::size_t>(i) * width];
      for (std::size_t c = 0; c < corrections.size(); ++c) values[c][i] = v[static_cast<std::size_t>(i) * width + 1 + c];
    }
    for (std::size_t c = 0; c < corrections.size(); ++c) {
      SweepRow row{corrections[c], N, centred, 0, 0, 0, true};
      ErrorSums error, from_none;
      for (long i = 0; i < R; ++i) {
        row.finite = row.finite && std::isfinite(values[c][i]);
        error.add(values[c][i] - reference[i]);
        from_none.add(values[c][i] - none[i]);
      }
      row.mean_error = error.stats().mean;
      row.max_error = error.stats().max;
      row.max_diff_from_none = from_none.stats().max;
      rows.push_back(row);
    }
  }
  bar.finish();
  return rows;
}

double render_seconds(const RenderScenes& s, const Camera& camera, const DiscreteConfig& config, int repeats) {
  const GridField& grid = std::get<GridField>(s.sampled.field);
  const DiscreteRaycaster<GridField> caster(grid, s.sampled.box, s.sampled.transfer, s.sampled.background, config);
  const std::vector<Ray> rays = camera_rays(camera);
  double best = std::numeric_limits<double>::infinity();
  volatile double sink = 0;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    double sum = 0;
    for (const Ray& ray : rays) sum += caster.cast(ray).value;
    const auto t1 = std::chrono::steady_clock::now();
    sink = sink + sum;
    best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
  }
  return best;
}

}  // namespace vrv
