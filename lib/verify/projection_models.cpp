#include "lib/verify/projection_models.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include <fmt/format.h>

#include "lib/image_loop.h"
#include "lib/projection/projection_reference.h"
#include "lib/util/progress.h"
#include "lib/util/task_rows.h"
#include "lib/verify/diagnosis.h"
#include "lib/verify/model_catalogue.h"
#include "lib/work_estimate.h"

namespace vrv {
namespace {

std::string rule_text(ProjectionMode mode, XrayRule rule) {
  if (is_mip(mode)) return "the largest sample";
  switch (rule) {
    case XrayRule::riemann: return "Riemann sum (each sample times its step)";
    case XrayRule::trapezoid: return "trapezoid rule between entry, samples and exit";
    default: return "Simpson's rule between entry, samples and exit";
  }
}

ProjectionModel model(const Scene& scene, ProjectionMode mode, Strategy strategy, const char* placement,
                      XrayRule rule, const std::vector<double>& steps) {
  ProjectionModel m;
  m.label.placement = std::string(strategy_name(strategy));
  m.label.rule = is_mip(mode) ? "max" : std::string(xray_rule_name(rule));
  m.label.opacity = "none (projection)";
  m.label.name = fmt::format("{} {}: {} placement, {}", projection_mode_name(mode), is_mip(mode) ? "max" : "rule",
                             placement, rule_text(mode, rule));
  for (double h : steps) {
    DiscreteProjectionConfig c;
    c.mode = mode;
    c.rule = rule;
    c.sampling.strategy = strategy;
    c.sampling.step = h;
    c.sampling.dims = scene.dims;
    m.per_step.push_back(c);
  }
  return m;
}

// Whether tau's largest value over the transfer function's breakpoints is a corner: an interior
// breakpoint where tau rises on the left and falls on the right (or jumps down).
bool extinction_peaks_at_a_corner(const TransferFunction& tf) {
  const std::vector<double>& b = tf.breakpoints();
  std::size_t top = 0;
  for (std::size_t i = 1; i < b.size(); ++i)
    if (tf.extinction(b[i]) > tf.extinction(b[top])) top = i;
  if (top == 0 || top + 1 >= b.size()) return false;
  const double peak = tf.extinction(b[top]);
  return tf.extinction(value_inside(b[top - 1], b[top])) < peak && tf.extinction(value_inside(b[top], b[top + 1])) < peak;
}

}  // namespace

double expected_projection_order(ProjectionMode mode, const TransferFunction& tf) {
  return mode == ProjectionMode::mip_classified && extinction_peaks_at_a_corner(tf) ? 1 : 2;
}

std::string projection_cache_tag(ProjectionMode mode) {
  return fmt::format("\n# projection mode = {}\n", projection_mode_name(mode));
}

ReferenceImage projection_reference_image(const Scene& scene, const Camera& camera, ProjectionMode mode, double tol,
                                          bool progress) {
  require_grey(scene, "scene", "projection_reference_image");
  ReferenceImage r(camera.width, camera.height);  // a projection has no optical depth: 0
  Progress bar("reference", pixel_count(camera), progress);
  ImageLoopHooks hooks;
  hooks.progress = [&](long done) { bar.advance(done); };
  visit_field(scene, [&](const auto& field) {
    image_loop_into(
        camera, {}, [&](const Ray& ray) { return projection_reference(field, scene.box, scene.transfer, ray, mode, {tol}); },
        [&](long i, const ProjectionResult& v) {
          r.pixels[i] = v.value;
          // A result that missed its tolerance (a work cap) is reported as missing it.
          r.error_estimate[i] = v.tolerance_met ? v.error_estimate : std::max(v.error_estimate, 2 * tol);
        },
        hooks);
  });
  bar.finish();
  return r;
}

std::vector<ProjectionModel> projection_models(const Scene& scene, ProjectionMode mode,
                                               const std::vector<double>& steps) {
  std::vector<ProjectionModel> out;
  for (auto [strategy, placement] : diagnosis_placements()) {
    if (is_mip(mode)) {
      out.push_back(model(scene, mode, strategy, placement, XrayRule::trapezoid, steps));
      continue;
    }
    for (XrayRule rule : {XrayRule::riemann, XrayRule::trapezoid, XrayRule::simpson})
      out.push_back(model(scene, mode, strategy, placement, rule, steps));
  }
  return out;
}

std::vector<Candidate> diagnose_projection(const Scene& scene, const Camera& camera, ProjectionMode mode,
                                           const std::vector<const ImageWithStep*>& sorted, int channel,
                                           const VerifyOptions& opt) {
  std::vector<double> steps;
  for (const auto* im : sorted) steps.push_back(im->step);
  const std::vector<ProjectionModel> models = projection_models(scene, mode, steps);
  const std::vector<long> pixels = diagnosis_pixels(camera.width, camera.height);
  // (model, step) casts in parallel (dealt to the ranks under MPI), each into its own row of the
  // table: the report does not depend on the thread or rank count.
  const std::size_t n = pixels.size();
  const auto cast_pair = [&](long pair, std::span<double> row) {
    const std::size_t m = pair / steps.size(), k = pair % steps.size();
    const std::vector<double> cast = visit_field(scene, [&](const auto& field) {
      return image_loop(camera, pixels, [&](const Ray& ray) {
        return discrete_projection(field, scene.box, scene.transfer, ray, models[m].per_step[k]).value;
      });
    });
    std::copy(cast.begin(), cast.end(), row.begin());
  };
  const std::vector<double> casts =
      task_rows(static_cast<long>(models.size() * steps.size()), static_cast<long>(n), cast_pair);
  std::vector<Candidate> out;
  for (std::size_t m = 0; m < models.size(); ++m) {
    Candidate c = models[m].label;
    double sum_sq = 0, max = 0;
    long count = 0;
    for (std::size_t k = 0; k < sorted.size(); ++k)
      for (std::size_t j = 0; j < pixels.size(); ++j) {
        const double u = comparable(sorted[k]->image, channel, pixels[j], 0.0, opt.alpha);
        if (!std::isfinite(u)) continue;
        const double d = u - casts[(m * steps.size() + k) * n + j];
        sum_sq += d * d, max = std::max(max, std::abs(d)), ++count;
      }
    c.rms = count ? std::sqrt(sum_sq / count) : std::numeric_limits<double>::quiet_NaN();
    c.max = max;
    c.pixels = static_cast<long>(pixels.size());
    out.push_back(c);
  }
  std::stable_sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) { return a.rms < b.rms; });
  return out;
}

double projection_diagnosis_work(const Scene& scene, const Camera& camera, ProjectionMode mode,
                                 const std::vector<double>& steps) {
  const double pixels = static_cast<double>(camera.width) * camera.height;
  const double fine = static_cast<double>(diagnosis_pixels(camera.width, camera.height).size());
  double work = 0;
  for (const ProjectionModel& m : projection_models(scene, mode, steps))
    for (const DiscreteProjectionConfig& c : m.per_step) {
      DiscreteConfig cast;  // the same placement's samples
      cast.sampling = c.sampling;
      const double factor = !is_mip(mode) && c.rule == XrayRule::simpson ? 2 : 1;
      work += factor * camera_work(scene, camera, 0, &cast) / pixels * fine;
    }
  return work;
}

}  // namespace vrv
