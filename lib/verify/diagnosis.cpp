#include "lib/verify/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <numeric>

#include "lib/image_loop.h"
#include "lib/util/task_rows.h"
#include "lib/verify/model_catalogue.h"
#include "lib/work_estimate.h"
#include "lib/util/not_a_number.h"

namespace vrv {
namespace {

using Casts = std::vector<std::vector<double>>;  // one model's pixels, per step

// A regular lattice of about `target` pixels (all of them when the image has no more), one at
// the centre of each cell: deterministic, and spread over the whole image.
std::vector<long> lattice_pixels(int w, int h, long target) {
  const long n = static_cast<long>(w) * h;
  const int stride = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n) / target))));
  std::vector<long> p;
  for (int y = stride / 2; y < h; y += stride)
    for (int x = stride / 2; x < w; x += stride) p.push_back(static_cast<long>(y) * w + x);
  return p;
}

// Whether two models' pixels agree to rounding (1e-11 of the largest value): then the later,
// more elaborate one (a centred table of a transfer function whose breakpoints fall on its
// entries, premultiplied colour where alpha = a) says nothing the earlier one does not.
bool same_pixels(const Casts& a, const Casts& b) {
  double scale = 1, diff = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    for (std::size_t j = 0; j < a[k].size(); ++j) {
      scale = std::max(scale, std::abs(a[k][j]));
      diff = std::max(diff, std::abs(a[k][j] - b[k][j]));
    }
  return diff <= 1e-11 * scale;
}

// Every listed model at every step on `pixels`, (model, step) pairs in parallel (dealt to the
// ranks under MPI, lib/util/task_rows.h); each pair fills its own row, so the casts do not depend
// on the thread or rank count.
std::vector<Casts> cast_models(const Scene& scene, const Camera& camera, const std::vector<Model>& models,
                               const std::vector<std::size_t>& which, const std::vector<long>& pixels) {
  const std::size_t steps = models.empty() ? 0 : models.front().per_step.size();
  const auto cast_pair = [&](long pair, std::span<double> row) {
    const std::size_t m = which[pair / steps], k = pair % steps;
    const std::vector<double> cast = cast_pixels(scene, camera, models[m].per_step[k], pixels);
    std::copy(cast.begin(), cast.end(), row.begin());
  };
  const std::vector<double> rows =
      task_rows(static_cast<long>(which.size() * steps), static_cast<long>(pixels.size()), cast_pair);
  std::vector<Casts> out(models.size());
  for (std::size_t i = 0; i < which.size(); ++i)
    for (std::size_t k = 0; k < steps; ++k) {
      const auto first = rows.begin() + static_cast<std::ptrdiff_t>((i * steps + k) * pixels.size());
      out[which[i]].emplace_back(first, first + static_cast<std::ptrdiff_t>(pixels.size()));
    }
  return out;
}

// RMS and max over every image of the difference between the images' pixels and a model's.
void measure(Candidate& c, const Casts& casts, const std::vector<const ImageWithStep*>& sorted, int channel,
             const std::vector<long>& pixels, double background, AlphaMode alpha) {
  double sum_sq = 0, max = 0;
  long count = 0;
  for (std::size_t k = 0; k < sorted.size(); ++k)
    for (std::size_t j = 0; j < pixels.size(); ++j) {
      const double u = comparable(sorted[k]->image, channel, pixels[j], background, alpha);
      if (!std::isfinite(u)) continue;
      const double d = u - casts[k][j];
      sum_sq += d * d, max = std::max(max, std::abs(d)), ++count;
    }
  c.rms = count ? std::sqrt(sum_sq / count) : kNaN;
  c.max = max;
  c.pixels = static_cast<long>(pixels.size());
}

// The models ranked by their RMS (ties in catalogue order); NaN last.
std::vector<std::size_t> ranked(const std::vector<Candidate>& c, const std::vector<std::size_t>& which) {
  std::vector<std::size_t> order = which;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return !std::isnan(c[a].rms) && (std::isnan(c[b].rms) || c[a].rms < c[b].rms);
  });
  return order;
}

// The leaders of a ranking: the first kMinLeaders, and any other within kLeaderFactor of the best.
std::vector<bool> leaders(const std::vector<Candidate>& c, const std::vector<std::size_t>& order) {
  std::vector<bool> lead(c.size());
  for (std::size_t r = 0; r < order.size(); ++r)
    lead[order[r]] = r < kMinLeaders || c[order[r]].rms <= kLeaderFactor * c[order.front()].rms;
  return lead;
}

std::vector<std::size_t> indices(std::size_t n) {
  std::vector<std::size_t> all(n);
  std::iota(all.begin(), all.end(), std::size_t{0});
  return all;
}

// Every model's RMS on the ranking pixels, and its casts there.
struct Ranking {
  std::vector<Casts> casts;
  std::vector<Candidate> candidates;
};
Ranking rank(const Scene& scene, const Camera& camera, const std::vector<Model>& models,
             const std::vector<const ImageWithStep*>& sorted, int channel, const std::vector<long>& pixels,
             AlphaMode alpha) {
  Ranking r{cast_models(scene, camera, models, indices(models.size()), pixels), {}};
  for (std::size_t m = 0; m < models.size(); ++m) {
    r.candidates.push_back(models[m].label);
    measure(r.candidates[m], r.casts[m], sorted, channel, pixels, scene.background, alpha);
  }
  return r;
}

// A shaded scene's gradient scheme nearest the images: each scheme with each of the ranking's first
// kMinLeaders models, on the ranking pixels of the finest image (where the discretisation differs
// least, and a scheme's floor does not shrink).
GradientChoice nearest_gradient(const Scene& scene, const Camera& camera, const std::vector<Model>& models,
                                const std::vector<std::size_t>& order, const std::vector<const ImageWithStep*>& sorted,
                                int channel, const std::vector<long>& pixels, AlphaMode alpha) {
  const std::vector<GradientChoice> choices = gradient_choices(scene);
  std::vector<Model> probes;  // (choice, model) pairs at the finest step
  for (const GradientChoice& g : choices)
    for (std::size_t r = 0; r < std::min(kMinLeaders, order.size()); ++r) {
      probes.push_back(with_gradient(models[order[r]], g, scene));
      probes.back().per_step = {probes.back().per_step.back()};
    }
  const Ranking r = rank(scene, camera, probes, {sorted.back()}, channel, pixels, alpha);
  const std::size_t nearest = ranked(r.candidates, indices(probes.size())).front();
  return choices[nearest / std::min(kMinLeaders, order.size())];
}

}  // namespace

std::vector<long> diagnosis_pixels(int width, int height) { return lattice_pixels(width, height, kDiagnosisPixels); }
std::vector<long> ranking_pixels(int width, int height) { return lattice_pixels(width, height, kRankingPixels); }

std::vector<Model> distinct_models(const Scene& scene, const std::vector<double>& steps, const VerifyOptions& opt) {
  std::vector<Model> out;
  for (Model& m : model_catalogue(scene, steps, opt))
    if (std::none_of(out.begin(), out.end(), [&](const Model& kept) { return same_model(kept, m, scene); }))
      out.push_back(std::move(m));
  return out;
}

std::vector<double> cast_pixels(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                                const std::vector<long>& pixels) {
  return visit_field(scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    const DiscreteRaycaster<F> caster = scene_raycaster(field, scene, config);
    return image_loop(camera, pixels, [&](const Ray& ray) { return caster.cast(ray).value; });
  });
}

std::vector<double> discrete_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config) {
  std::vector<long> all(static_cast<std::size_t>(camera.width) * camera.height);
  std::iota(all.begin(), all.end(), 0L);
  return cast_pixels(scene, camera, config, all);
}

// Coarse to fine: every distinct model is ranked on the ranking pixels; the leaders are cast again
// on the diagnosis pixels and reported first, by their RMS there, the rest after them by their
// ranking RMS.  A model whose pixels equal an earlier one's is left out (on the diagnosis pixels
// for a leader, on the ranking pixels otherwise).
std::vector<Candidate> diagnose(const Scene& scene, const Camera& camera,
                                const std::vector<const ImageWithStep*>& sorted, int channel,
                                const VerifyOptions& opt) {
  std::vector<double> steps;
  for (const auto* im : sorted) steps.push_back(im->step);
  const std::vector<long> coarse = ranking_pixels(camera.width, camera.height);
  std::vector<Model> models = distinct_models(scene, steps, opt);
  std::vector<std::size_t> all = indices(models.size());
  Ranking coarse_rank = rank(scene, camera, models, sorted, channel, coarse, opt.alpha);
  // A shaded scene: the models shade with the scheme nearest the images (ranked again when it is
  // not the default), and the nearest model is cast with every other scheme too, as leaders.
  if (!models.empty() && scene.shading) {
    const GradientChoice g =
        nearest_gradient(scene, camera, models, ranked(coarse_rank.candidates, all), sorted, channel, coarse, opt.alpha);
    if (g.scheme != GradientScheme::central || g.offset) {
      for (Model& m : models) m = with_gradient(m, g, scene);
      coarse_rank = rank(scene, camera, models, sorted, channel, coarse, opt.alpha);
    }
  }
  std::vector<Candidate>& c = coarse_rank.candidates;
  const std::vector<Casts>& coarse_casts = coarse_rank.casts;
  std::vector<bool> lead = leaders(c, ranked(c, all));
  if (!models.empty())
    for (Model& v : gradient_variants(models[ranked(c, all).front()], scene)) {
      if (std::any_of(models.begin(), models.end(), [&](const Model& m) { return same_model(m, v, scene); })) continue;
      c.push_back(v.label);
      models.push_back(std::move(v));
      lead.push_back(true);
      all.push_back(models.size() - 1);
    }
  std::vector<std::size_t> leading;
  for (std::size_t m : all)
    if (lead[m]) leading.push_back(m);
  const std::vector<long> fine = diagnosis_pixels(camera.width, camera.height);
  const std::vector<Casts> fine_casts = cast_models(scene, camera, models, leading, fine);
  // A leader is compared with the leaders kept before it on the diagnosis pixels, any other model
  // with every model kept before it on the ranking pixels (equal pixels rank alike, so a model
  // equal to a leader is one).
  std::vector<std::size_t> kept_leaders, kept_others, kept;
  for (std::size_t m : all) {
    const bool repeats = lead[m] ? std::any_of(kept_leaders.begin(), kept_leaders.end(),
                                               [&](std::size_t k) { return same_pixels(fine_casts[m], fine_casts[k]); })
                                 : std::any_of(kept.begin(), kept.end(),
                                               [&](std::size_t k) { return same_pixels(coarse_casts[m], coarse_casts[k]); });
    if (repeats) continue;
    if (lead[m]) measure(c[m], fine_casts[m], sorted, channel, fine, scene.background, opt.alpha);
    (lead[m] ? kept_leaders : kept_others).push_back(m);
    kept.push_back(m);
  }
  std::vector<Candidate> out;
  for (const auto* kept : {&kept_leaders, &kept_others})
    for (std::size_t m : ranked(c, *kept)) out.push_back(c[m]);
  return out;
}

double diagnosis_work(const Scene& scene, const Camera& camera, const std::vector<double>& steps,
                      const VerifyOptions& opt) {
  const double pixels = static_cast<double>(camera.width) * camera.height;
  const double coarse = static_cast<double>(ranking_pixels(camera.width, camera.height).size());
  const double fine = static_cast<double>(diagnosis_pixels(camera.width, camera.height).size());
  std::vector<double> per_model;  // samples of a model over all steps, per pixel
  for (const Model& m : distinct_models(scene, steps, opt)) {
    double samples = 0;
    for (const DiscreteConfig& config : m.per_step) samples += camera_work(scene, camera, 0, &config) / pixels;
    per_model.push_back(samples);
  }
  // The leaders: at least kMinLeaders, counted as the dearest.  A shaded scene's choice of the
  // gradient (every scheme with kMinLeaders models at the finest step, then the ranking again) and
  // its schemes on the nearest model (each counted as the dearest).
  std::sort(per_model.rbegin(), per_model.rend());
  double work = 0;
  if (const double schemes = static_cast<double>(gradient_choices(scene).size()); schemes > 0 && !per_model.empty())
    work += schemes * per_model.front() * (kMinLeaders * coarse + fine) +
            std::accumulate(per_model.begin(), per_model.end(), 0.0) * coarse;
  for (std::size_t m = 0; m < per_model.size(); ++m)
    work += per_model[m] * (coarse + (m < kMinLeaders ? fine : 0));
  return work;
}

}  // namespace vrv
