#include "lib/verify/fault_hints.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "lib/gradient_scheme.h"
#include "lib/util/not_a_number.h"

namespace vrv {
namespace {

struct OffsetFit {
  double entry = kNaN, exit = kNaN, explained = kNaN;  // shifts in units of the step; R^2
};

// e ~ d0 * dI/d(entry) + d1 * dI/d(exit) over the hit pixels, least squares.
OffsetFit fit_offsets(const ChannelReport& r, const PixelGeometry& g) {
  double aa = 0, ab = 0, bb = 0, ae = 0, be = 0, ee = 0;
  for (std::size_t i = 0; i < r.error.size(); ++i) {
    if (!g.hit[i] || !std::isfinite(r.error[i])) continue;
    const double a = g.d_entry[i], b = g.d_exit[i], e = r.error[i];
    aa += a * a, ab += a * b, bb += b * b, ae += a * e, be += b * e, ee += e * e;
  }
  const double det = aa * bb - ab * ab;
  if (!(det > 0) || !(ee > 0)) return {};
  const double d0 = (ae * bb - be * ab) / det, d1 = (be * aa - ae * ab) / det;
  const double ssr = ee - d0 * ae - d1 * be;  // residual of the normal-equation solution
  return {d0 / r.step, d1 / r.step, 1 - std::max(0.0, ssr) / ee};
}

// Correlation of errors between horizontal and vertical neighbours that both lie in the
// interior/jump pixels; near 1 for a discretisation error (smooth), near 0 for per-pixel noise.
double neighbour_correlation(const ChannelReport& r, const PixelGeometry& g, int w, int h) {
  double xy = 0, xx = 0, yy = 0;
  auto inside = [&](long i) {
    return (g.region[i] == Region::interior || g.region[i] == Region::tf_jump) && std::isfinite(r.error[i]);
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const long i = static_cast<long>(y) * w + x;
      if (!inside(i)) continue;
      for (long j : {x + 1 < w ? i + 1 : -1L, y + 1 < h ? i + w : -1L}) {
        if (j < 0 || !inside(j)) continue;
        xy += double(r.error[i]) * r.error[j], xx += double(r.error[i]) * r.error[i],
            yy += double(r.error[j]) * r.error[j];
      }
    }
  return xx > 0 && yy > 0 ? xy / std::sqrt(xx * yy) : kNaN;
}

// The quantisation named in a fault: the integers' (whatever type stored them) or a float's ulp.
std::string quantum_name(double quantum) {
  if (std::abs(quantum * 255 - 1) < 1e-9) return "8-bit (values on multiples of 1/255)";
  if (std::abs(quantum * 65535 - 1) < 1e-9) return "16-bit (values on multiples of 1/65535)";
  return quantum >= 1.0 / 65535 * 0.999 ? "integer" : "float";
}

const OrderReport* order_of(const VerifyReport& rep, OrderKind kind, const std::string& channel) {
  for (const OrderReport& o : rep.orders)
    if (o.kind == kind && o.channel == channel) return &o;
  return nullptr;
}

bool has(const std::vector<Fault>& faults, FaultKind kind) {
  return std::any_of(faults.begin(), faults.end(), [&](const Fault& f) { return f.kind == kind; });
}

// What the heuristics read: one channel of the finest and the coarsest image.
struct Evidence {
  const VerifyReport& rep;
  const PixelGeometry& geometry;
  const VerifyOptions& opt;
  int channel_count, colour;
  std::size_t images;
  const ChannelReport& finest;
  const ChannelReport& coarsest;
  const std::string& ch;
};

std::optional<Fault> quantisation(const Evidence& e) {
  const ChannelReport& finest = e.finest;
  const Metric m = e.opt.order_metric;
  if (!finest.at_floor) return std::nullopt;
  return Fault{FaultKind::quantisation,
               fmt::format("{} ({}): {} error {:.3g} is within twice the {} quantisation floor {:.3g}: no order "
                           "below it", finest.image, e.ch, metric_name(m), metric_value(finest.all(), m),
                           quantum_name(finest.quantum), m == Metric::max ? finest.floor_max : finest.floor_rms)};
}

// The errors are the first-order change of I under moving the samples.
std::optional<Fault> half_step_offset(const Evidence& e) {
  for (const ChannelReport* r : {&e.coarsest, &e.finest}) {
    const OffsetFit f = fit_offsets(*r, e.geometry);
    if (!(f.explained >= 0.5) || !(std::abs(f.entry) >= 0.3 && std::abs(f.entry) <= 0.7)) continue;
    return Fault{FaultKind::half_step_offset,
                 fmt::format("{} ({}): the error is {:.0f} % explained by moving the samples {:+.2f} "
                             "steps at the entry and {:+.2f} at the exit: the samples sit half a step "
                             "{} than a midpoint rule puts them", r->image, e.ch, 100 * f.explained,
                             f.entry, f.exit, f.entry > 0 ? "later" : "earlier"),
                 f.entry > 0 ? "samples at the end of each step" : "samples at the start of each step", 1};
  }
  return std::nullopt;
}

// The images agree with each other much better than with the reference.
std::optional<Fault> constant_floor(const Evidence& e) {
  const OrderReport* o = order_of(e.rep, OrderKind::reference, e.ch);
  const OrderReport* s = order_of(e.rep, OrderKind::self, e.ch);
  if (!o || !s || o->judgement.verdict != Verdict::stalls || s->errors.empty() || o->errors.empty() ||
      !(s->errors.back() < 0.2 * o->errors.back()))
    return std::nullopt;
  return Fault{FaultKind::constant_floor,
               fmt::format("{}: every image carries an error of {:.3g} ({}) that does not "
                           "shrink with the step, while the two finest differ by only {:.3g}: "
                           "a step-independent error (background, transfer function, "
                           "precision, camera, or a field other than the scene's: a grid "
                           "of an analytic field, as `vrv export` writes it; verify an "
                           "export against its scene.toml)", e.ch, o->errors.back(),
                           metric_name(e.opt.order_metric), s->errors.back())};
}

std::optional<Fault> border_band(const Evidence& e) {
  const RegionStats* band = e.finest.region(Region::silhouette);
  const RegionStats* inner = e.finest.region(Region::interior);
  const RegionStats* jump = e.finest.region(Region::tf_jump);
  const double inside_rms = std::max(inner ? inner->stats.rms : 0.0, jump ? jump->stats.rms : 0.0);
  if (!band || !inner || band->pixels == 0 || !(band->stats.rms > 3 * inside_rms) ||
      !(band->stats.rms > 2 * e.finest.floor_rms))
    return std::nullopt;
  std::vector<double> steps, errs;
  for (std::size_t k = 0; k < e.images; ++k) {
    const ChannelReport& r = e.rep.channels[k * e.channel_count + e.colour];
    steps.push_back(r.step);
    errs.push_back(r.region(Region::silhouette)->stats.rms);
  }
  const OrderEstimate f = fit_order(steps, errs);
  if (!(f.order < 1.5)) return std::nullopt;
  return Fault{FaultKind::first_order_border_band,
               fmt::format("{} ({}): RMS {:.3g} in the {}-pixel silhouette band against {:.3g} "
                           "inside, converging there at order {:.3g}: rays that graze the box "
                           "(entry/exit handling)", e.finest.image, e.ch, band->stats.rms,
                           e.opt.silhouette_band, inside_rms, f.order),
               "first-order handling of the ends of the ray (a partial step dropped or taken whole)", 1};
}

// Jittered start positions: zero-mean noise, uncorrelated between neighbours, and first order
// (a random fraction of a step); a step rounded per ray also decorrelates neighbours, but at the
// rule's own (second) order.  Jittered images differ from each other as much as from the
// reference: under a constant floor (the images agree with each other) the noise-like error is
// the floor's, not jitter.
std::optional<Fault> jitter(const Evidence& e, const std::vector<Fault>& found) {
  const double corr = neighbour_correlation(e.finest, e.geometry, e.rep.width, e.rep.height);
  const OrderReport* against = order_of(e.rep, OrderKind::reference, e.ch);
  const double order = against ? against->fit.order : kNaN;
  const RegionStats* inner = e.finest.region(Region::interior);
  if (has(found, FaultKind::constant_floor) || !inner || !(inner->pixels > 16) ||
      !(inner->stats.rms > 2 * e.finest.floor_rms) || !std::isfinite(corr) || !(std::abs(corr) < 0.3) ||
      !(std::abs(inner->stats.mean_signed) < 0.5 * inner->stats.rms) || !(order < 1.5))
    return std::nullopt;
  return Fault{FaultKind::jitter,
               fmt::format("{} ({}): interior error RMS {:.3g} with mean {:.3g} and neighbour correlation "
                           "{:.2f}: zero-mean noise, as from jittered start positions", e.finest.image, e.ch,
                           inner->stats.rms, inner->stats.mean_signed, corr),
               "jittered start positions (a random fraction of a step per pixel)", 1};
}

// Error concentrated at transfer-function jumps.
std::optional<Fault> error_at_jumps(const Evidence& e) {
  const RegionStats* inner = e.finest.region(Region::interior);
  const RegionStats* jump = e.finest.region(Region::tf_jump);
  if (!jump || !inner || jump->pixels == 0 || !(jump->stats.rms > 3 * inner->stats.rms) ||
      !(jump->stats.rms > 2 * e.finest.floor_rms))
    return std::nullopt;
  return Fault{FaultKind::error_at_tf_jumps,
               fmt::format("{} ({}): RMS {:.3g} on the {} pixels whose rays cross a jump against "
                           "{:.3g} elsewhere inside", e.finest.image, e.ch, jump->stats.rms,
                           jump->pixels, inner->stats.rms)};
}

// The nearest model takes the opacity per sample, far nearer than any corrected one.
std::optional<Fault> missing_opacity_correction(const VerifyReport& rep) {
  if (rep.diagnosis.size() < 2 || rep.diagnosis.front().opacity_corrected) return std::nullopt;
  const Candidate& best = rep.diagnosis.front();
  const auto corrected = std::find_if(rep.diagnosis.begin(), rep.diagnosis.end(),
                                      [](const Candidate& c) { return c.opacity_corrected; });
  const double corrected_rms = corrected == rep.diagnosis.end() ? kNaN : corrected->rms;
  if (!(best.rms < 0.3 * corrected_rms)) return std::nullopt;
  return Fault{FaultKind::missing_opacity_correction,
               fmt::format("nearest model: {} (RMS {:.3g}); the nearest corrected model is "
                           "{:.3g} away", best.name, best.rms, corrected_rms)};
}

// A shaded image whose nearest model takes its gradient otherwise than exactly, far nearer than
// that model with the field's exact gradient (gradient_variants, model_catalogue.h): the images'
// gradient scheme leaves an error of its own, which a finer step does not remove.
std::optional<Fault> gradient_floor(const VerifyReport& rep) {
  const auto exact = [](const Candidate& c) {
    return c.gradient_choice && c.gradient_choice->scheme == GradientScheme::analytic;
  };
  if (rep.diagnosis.empty() || !rep.diagnosis.front().gradient_choice || exact(rep.diagnosis.front()))
    return std::nullopt;
  const Candidate& best = rep.diagnosis.front();
  // The same model with the exact gradient; else (another leader came first on the diagnosis
  // pixels) the nearest model with it on the same pixels.
  const auto exact_on_same_pixels = [&](const Candidate& c) { return exact(c) && c.pixels == best.pixels; };
  auto twin = std::find_if(rep.diagnosis.begin(), rep.diagnosis.end(), [&](const Candidate& c) {
    return exact_on_same_pixels(c) && c.placement == best.placement && c.rule == best.rule &&
           c.opacity == best.opacity && c.color == best.color && c.table == best.table;
  });
  if (twin == rep.diagnosis.end()) twin = std::find_if(rep.diagnosis.begin(), rep.diagnosis.end(), exact_on_same_pixels);
  if (twin == rep.diagnosis.end() || !(best.rms < 0.3 * twin->rms)) return std::nullopt;
  return Fault{FaultKind::gradient_floor,
               fmt::format("nearest model: {} (RMS {:.3g}); with the field's exact gradient it is {:.3g} away: "
                           "the images shade with approximate gradients, an error a finer step does not remove",
                           best.name, best.rms, twin->rms),
               fmt::format("gradient {}", best.gradient)};
}

}  // namespace

std::vector<Fault> find_faults(const VerifyReport& rep, const PixelGeometry& g, int channel_count, int colour,
                               const VerifyOptions& opt) {
  std::vector<Fault> faults;
  if (rep.channels.empty()) return faults;
  // The finest image is the last (the images are sorted by decreasing step).
  const std::size_t images = rep.channels.size() / channel_count;
  const ChannelReport& finest = rep.channels[(images - 1) * channel_count + colour];
  const Evidence e{rep, g, opt, channel_count, colour, images, finest, rep.channels[colour], finest.channel};
  const auto add = [&](std::optional<Fault> f) {
    if (f) faults.push_back(std::move(*f));
  };
  add(quantisation(e));
  add(half_step_offset(e));
  add(constant_floor(e));
  add(border_band(e));
  add(jitter(e, faults));
  add(error_at_jumps(e));
  add(missing_opacity_correction(rep));
  add(gradient_floor(rep));
  return faults;
}

}  // namespace vrv
