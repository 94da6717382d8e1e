#include "lib/verify/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "lib/util/parallel.h"
#include "lib/verify/model_catalogue.h"

namespace vrv {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Pixels the diagnosis compares: all of them up to 128 x 128, else a regular lattice of about
// that many, so that the diagnosis stays a matter of seconds.
std::vector<long> diagnosis_pixels(int w, int h) {
  const long n = static_cast<long>(w) * h;
  const int stride = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n) / 16384.0))));
  std::vector<long> p;
  for (int y = stride / 2; y < h; y += stride)
    for (int x = stride / 2; x < w; x += stride) p.push_back(static_cast<long>(y) * w + x);
  return p;
}

// Whether two models' pixels agree to rounding (1e-11 of the largest value): then the later,
// more elaborate one (a centred table of a transfer function whose breakpoints fall on its
// entries, premultiplied colour where alpha = a) says nothing the earlier one does not.
bool same_pixels(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
  double scale = 1, diff = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    for (std::size_t j = 0; j < a[k].size(); ++j) {
      scale = std::max(scale, std::abs(a[k][j]));
      diff = std::max(diff, std::abs(a[k][j] - b[k][j]));
    }
  return diff <= 1e-11 * scale;
}

}  // namespace

std::vector<double> cast_pixels(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                                const std::vector<long>& pixels) {
  std::vector<double> out(pixels.size());
  visit_field(scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    const DiscreteRaycaster<F> caster(field, scene.box, scene.transfer, scene.background, config);
    parallel_for_index(static_cast<long>(pixels.size()), [&](long k) {
      const long i = pixels[k];
      out[k] = caster.cast(camera.ray(static_cast<int>(i % camera.width), static_cast<int>(i / camera.width))).value;
    });
  });
  return out;
}

std::vector<double> discrete_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config) {
  std::vector<long> all(static_cast<std::size_t>(camera.width) * camera.height);
  std::iota(all.begin(), all.end(), 0L);
  return cast_pixels(scene, camera, config, all);
}

std::vector<Candidate> diagnose(const Scene& scene, const Camera& camera,
                                const std::vector<const ImageWithStep*>& sorted, int channel,
                                const VerifyOptions& opt) {
  std::vector<double> steps;
  for (const auto* im : sorted) steps.push_back(im->step);
  const std::vector<long> pixels = diagnosis_pixels(camera.width, camera.height);
  std::vector<Candidate> out;
  std::vector<std::vector<std::vector<double>>> kept;  // the pixels of every model kept, per step
  for (Model& m : model_catalogue(scene, steps, opt)) {
    std::vector<std::vector<double>> casts;
    for (std::size_t k = 0; k < sorted.size(); ++k) casts.push_back(cast_pixels(scene, camera, m.per_step[k], pixels));
    if (std::any_of(kept.begin(), kept.end(), [&](const auto& other) { return same_pixels(casts, other); }))
      continue;
    double sum_sq = 0, max = 0;
    long count = 0;
    for (std::size_t k = 0; k < sorted.size(); ++k)
      for (std::size_t j = 0; j < pixels.size(); ++j) {
        const double u = comparable(sorted[k]->image, channel, pixels[j], scene.background, opt.alpha);
        if (!std::isfinite(u)) continue;
        const double d = u - casts[k][j];
        sum_sq += d * d, max = std::max(max, std::abs(d)), ++count;
      }
    m.label.rms = count ? std::sqrt(sum_sq / count) : kNaN;
    m.label.max = max;
    out.push_back(m.label);
    kept.push_back(std::move(casts));
  }
  std::stable_sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) { return a.rms < b.rms; });
  return out;
}

}  // namespace vrv
