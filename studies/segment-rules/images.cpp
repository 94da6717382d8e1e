// Image error of each segment rule against the reference integrator, per pixel, at a ladder of
// steps; the observed order is the least-squares slope of log(mean error) against log(step).
#include <algorithm>
#include <cmath>
#include <type_traits>

#include <fmt/format.h>

#include "lib/discrete_raycast.h"
#include "lib/image_loop.h"
#include "lib/metrics.h"
#include "lib/order_estimate.h"
#include "lib/reference_integrator.h"
#include "lib/util/progress.h"
#include "lib/work_estimate.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/reference_audit.h"
#include "studies/segment-rules/segment_rules.h"

namespace vrv {
namespace {

DiscreteConfig step_config(SegmentRule rule, Strategy strategy, double h, const Scene& scene) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = strategy;
  c.sampling.step = h;
  c.sampling.dims = scene.dims;
  return c;
}

Camera render_camera(const RenderSpec& spec, bool quick) {
  Camera camera = *spec.scene.camera;
  if (quick) {
    camera.width = spec.quick_width;
    camera.height = spec.quick_height;
  }
  return camera;
}

}  // namespace

void add_render_work(const RenderSpec& spec, const std::vector<RuleSpec>& rules, Strategy strategy,
                     double reference_tol, bool quick, StudyWork& work) {
  const Camera camera = render_camera(spec, quick);
  double per_ray = reference_evaluations(spec.scene, reference_tol);
  for (const RuleSpec& r : rules)
    for (double h : quick ? spec.quick_steps : spec.steps)
      per_ray += discrete_samples(step_config(r.rule, strategy, h, spec.scene), spec.scene);
  work.add(fmt::format("images {}", spec.name), static_cast<double>(camera.width) * camera.height, per_ray);
}

RenderResult run_render(const RenderSpec& spec, const std::vector<RuleSpec>& rules, Strategy strategy,
                        double reference_tol, ReferenceAudit& audit, bool quick, bool progress, Checkpoints* checkpoints,
                        const std::string& checkpoint_key) {
  const Camera camera = render_camera(spec, quick);
  const std::vector<double>& steps = quick ? spec.quick_steps : spec.steps;
  const std::size_t R = rules.size(), S = steps.size(), per_pixel = R * S;
  const long n = static_cast<long>(camera.width) * camera.height;
  const auto map_index = static_cast<std::size_t>(
      std::find(steps.begin(), steps.end(), spec.map_step) - steps.begin());

  RenderResult out;
  out.width = camera.width;
  out.height = camera.height;
  out.reference = Image(camera.width, camera.height);
  // Per pixel: hit, reference value, then (error, samples) per (rule, step).
  const std::size_t width = 2 + 2 * per_pixel;
  std::vector<double> records;

  const Scene& scene = spec.scene;
  visit_field(scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    std::vector<DiscreteRaycaster<F>> casters;
    casters.reserve(per_pixel);
    for (const RuleSpec& r : rules)
      for (double h : steps) {
        const DiscreteConfig c = step_config(r.rule, strategy, h, scene);
        validate(c, std::is_same_v<F, GridField>);
        casters.emplace_back(field, scene.box, scene.transfer, scene.background, c);
      }
    Progress bar("segment-rules " + spec.name, n, progress);
    ImageLoopHooks hooks;
    hooks.block = camera.width;  // one image row is one checkpoint
    hooks.progress = [&](long done) { bar.advance(done); };
    records = image_records(camera, {}, width, [&](const Ray& ray, std::span<double> v) {
      const ReferenceResult ref =
          audited_reference(audit, field, scene.box, scene.transfer, scene.background, ray, {reference_tol});
      v[0] = ref.hit ? 1 : 0;
      v[1] = ref.value;
      for (std::size_t k = 0; k < per_pixel; ++k) {
        const DiscreteResult d = casters[k].cast(ray);
        v[2 + 2 * k] = d.value - ref.value;
        v[3 + 2 * k] = static_cast<double>(d.samples);
      }
    }, hooks, checkpoint_blocks(checkpoints, checkpoint_key));
    bar.finish();
  });
  std::vector<double> error(static_cast<std::size_t>(n) * per_pixel);  // signed
  std::vector<long> samples(error.size());
  std::vector<char> hit(static_cast<std::size_t>(n));
  for (std::size_t pixel = 0; pixel < static_cast<std::size_t>(n); ++pixel) {
    const double* v = records.data() + pixel * width;
    hit[pixel] = v[0] != 0;
    out.reference.pixels[pixel] = static_cast<float>(v[1]);
    for (std::size_t k = 0; k < per_pixel; ++k) {
      error[pixel * per_pixel + k] = v[2 + 2 * k];
      samples[pixel * per_pixel + k] = static_cast<long>(v[3 + 2 * k]);
    }
  }

  // Reductions in pixel order: the same bits for any thread count.
  for (long i = 0; i < n; ++i) out.hit_pixels += hit[static_cast<std::size_t>(i)];
  const double hits = static_cast<double>(std::max(out.hit_pixels, 1L));
  for (std::size_t r = 0; r < R; ++r) {
    std::vector<double> means;
    for (std::size_t s = 0; s < S; ++s) {
      const std::size_t k = r * S + s;
      ImageErrorRow row{spec.name, rules[r].rule, steps[s], 0, 0, 0};
      for (long i = 0; i < n; ++i) {
        const auto pixel = static_cast<std::size_t>(i);
        if (!hit[pixel]) continue;
        const double e = std::abs(error[pixel * per_pixel + k]);
        row.max_error = std::max(row.max_error, e);
        row.mean_error += e;
        row.samples_per_ray += static_cast<double>(samples[pixel * per_pixel + k]);
      }
      row.mean_error /= hits;
      row.samples_per_ray /= hits;
      means.push_back(row.mean_error);
      out.rows.push_back(row);
    }
    out.fits.push_back(estimate_order(steps, means));
    Image map(camera.width, camera.height);
    for (long i = 0; i < n; ++i) {
      const auto pixel = static_cast<std::size_t>(i);
      map.pixels[pixel] = static_cast<float>(error[pixel * per_pixel + r * S + map_index]);
    }
    out.error_maps.push_back(std::move(map));
  }
  return out;
}

}  // namespace vrv
