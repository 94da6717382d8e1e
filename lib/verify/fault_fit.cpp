#include "lib/verify/fault_fit.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <tuple>
#include <utility>

#include <boost/math/tools/minima.hpp>
#include <fmt/format.h>

#include "lib/image_loop.h"
#include "lib/verify/diagnosis.h"
#include "lib/util/not_a_number.h"

namespace vrv {
namespace {

constexpr int kScanPoints = 9;     // a parameter's bracket is scanned first, then refined by Brent
constexpr int kBrentBits = 20;
constexpr std::size_t kDifferenceImages = 3;  // the coarsest images pick the discretisation model
constexpr std::uintmax_t kBrentIterations = 40;

// vrv's model of the renderer, perturbed by an entry.
struct Perturbed {
  Scene scene;
  Camera camera;
  DiscreteConfig config;
};

// One fault class: how a renderer with it differs from vrv's model, with its parameter p.
struct Entry {
  const char* id;
  const char* name;
  const char* parameter;  // "" without one
  double lo = 0, hi = 0;  // the bracket p is fitted in
  bool log_scan = false;  // scan the bracket evenly in log p (ratios)
  std::function<bool(const Scene&, const Camera&)> applies;
  std::function<void(Perturbed&, double)> perturb;  // the model's scene, camera or configuration
  std::function<long(long, int, int)> remap;        // the pixel whose ray pixel i shows (w, h)
  std::function<double(double, double)> curve;      // the output curve on a value
  std::function<std::string(double)> describe;
  // The ray pixel i is cast along (none: the camera's, through the pixel centre).
  std::function<Ray(const Camera&, long, double)> ray = {};
  bool integer = false;  // the parameter takes whole values (the scan's points are whole)
};

bool always(const Scene&, const Camera&) { return true; }

const GridField* grid_of(const Scene& scene) { return std::get_if<GridField>(&scene.field); }

// The transfer function read at map(v) instead of v (map affine and increasing): its curves'
// control points moved to map's inverse.
TransferFunction domain_mapped(const TransferFunction& tf, const std::function<double(double)>& inverse) {
  const auto moved = [&](const PiecewiseLinear& curve) {
    std::vector<ControlPoint> points = curve.points();
    for (ControlPoint& c : points) c.v = inverse(c.v);
    return PiecewiseLinear(points);
  };
  return tf.convention() == Convention::opacity_color
             ? TransferFunction::opacity_color(moved(tf.first()), moved(tf.second()), tf.unit_length())
             : TransferFunction::emission_extinction(moved(tf.first()), moved(tf.second()));
}

double domain_range(const TransferFunction& tf) { return tf.breakpoints().back() - tf.breakpoints().front(); }

// The opacity of a sample corrected with a reference step c times the sample distance: for
// emission/extinction, g and tau times c; for opacity per unit distance L, the unit L / c.
TransferFunction opacity_scaled(const TransferFunction& tf, double c) {
  if (tf.convention() == Convention::opacity_color)
    return TransferFunction::opacity_color(tf.first(), tf.second(), tf.unit_length() / c);
  const auto times = [&](const PiecewiseLinear& curve) {
    std::vector<ControlPoint> points = curve.points();
    for (ControlPoint& p : points) p.y *= c;
    return PiecewiseLinear(points);
  };
  return TransferFunction::emission_extinction(times(tf.first()), times(tf.second()));
}

// One voxel along each axis: the grid's spacing, else the box over the scene's nominal dims.
Vec3 voxel(const Scene& scene) {
  const Vec3 extent = scene.box.extent();
  const GridField* g = grid_of(scene);
  Vec3 v;
  for (int a = 0; a < 3; ++a) {
    const int n = g ? g->resolution()[a] : scene.dims[a];
    v[a] = extent[a] / std::max(1, g && g->layout() == GridLayout::node ? n - 1 : n);
  }
  return v;
}

double srgb_encode(double x) {
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
}

// The transfer function read from a table of `entries` values per curve at evenly spaced values
// over its breakpoints' range, each stored in `bits` bits (rounded to the nearest multiple of the
// curve's largest value / (2^bits - 1), ties to even), read with linear interpolation between entries.
TransferFunction quantised_table(const TransferFunction& tf, int entries, int bits) {
  const double lo = tf.breakpoints().front(), range = domain_range(tf);
  const double levels = std::ldexp(1.0, bits) - 1;
  const auto table = [&](const PiecewiseLinear& curve) {
    const double top = curve.max_value();
    std::vector<ControlPoint> points;
    for (int i = 0; i < entries; ++i) {
      const double v = lo + range * i / (entries - 1);
      // Ties to even, as IEEE conversions (and GPUs' float-to-unorm) round: a linear curve's
      // entries often land on exact halves.
      points.push_back({v, top > 0 ? std::nearbyint(curve(v) / top * levels) / levels * top : curve(v)});
    }
    return PiecewiseLinear(points);
  };
  return tf.convention() == Convention::opacity_color
             ? TransferFunction::opacity_color(table(tf.first()), table(tf.second()), tf.unit_length())
             : TransferFunction::emission_extinction(table(tf.first()), table(tf.second()));
}

constexpr int kQuantisedEntries = 256;

std::string percent_off(double s, const char* more, const char* less) {
  return fmt::format("{:.1f} % {}", 100 * std::abs(s - 1), s > 1 ? more : less);
}

// The catalogue.  A new fault class is one entry here.
const std::vector<Entry>& entries() {
  static const std::vector<Entry> kEntries = {
      {"rows_flipped", "image rows flipped", "", 0, 0, false, always, {},
       [](long i, int w, int h) { return static_cast<long>(h - 1 - i / w) * w + i % w; }, {},
       [](double) { return std::string("image rows flipped (row 0 at the bottom)"); }},
      {"columns_flipped", "image columns flipped", "", 0, 0, false, always, {},
       [](long i, int w, int) { return (i / w) * w + (w - 1 - i % w); }, {},
       [](double) { return std::string("image columns flipped (column 0 at the right)"); }},
      {"transposed", "image transposed", "", 0, 0, false,
       [](const Scene&, const Camera& c) { return c.width == c.height; }, {},
       [](long i, int w, int) { return (i % w) * w + i / w; }, {},
       [](double) { return std::string("image transposed (rows and columns swapped)"); }},
      {"srgb", "output sRGB-encoded", "", 0, 0, false, always, {}, {},
       [](double v, double) { return srgb_encode(v); },
       [](double) { return std::string("output sRGB-encoded (the sRGB curve on the linear result)"); }},
      {"gamma", "output gamma-encoded", "gamma", 0.4, 4, true, always, {}, {},
       [](double v, double g) { return std::pow(std::max(v, 0.0), 1 / g); },
       [](double g) { return fmt::format("output gamma-encoded, value^(1/{:.2f})", g); }},
      {"fov_scale", "field of view scale", "scale", 0.9, 1.1, false,
       [](const Scene&, const Camera& c) { return c.projection != Projection::fan; },
       [](Perturbed& m, double s) {
         (m.camera.projection == Projection::perspective ? m.camera.fov_degrees : m.camera.extent) *= s;
       },
       {}, {}, [](double s) { return "field of view " + percent_off(s, "wider", "narrower"); }},
      {"tf_domain_scale", "transfer-function domain scale", "scale", 0.9, 1.1, false, always,
       [](Perturbed& m, double s) { m.scene.transfer = domain_mapped(m.scene.transfer, [s](double v) { return v / s; }); },
       {}, {},
       [](double s) {
         return fmt::format("transfer-function domain scaled by {:.4f} before lookup{}", s,
                            std::abs(s - 255.0 / 256) < 5e-4 ? " (255/256: a 256-entry table read as 255)" : "");
       }},
      {"tf_domain_offset", "transfer-function domain offset", "offset (fraction of the range)", -0.05, 0.05, false,
       always,
       [](Perturbed& m, double o) {
         const double shift = o * domain_range(m.scene.transfer);
         m.scene.transfer = domain_mapped(m.scene.transfer, [shift](double v) { return v - shift; });
       },
       {}, {},
       [](double o) {
         return fmt::format("transfer-function domain offset by {:+.4f} of its range before lookup "
                            "({:+.2f} entries of a 256-entry table)", o, o * 255);
       }},
      {"termination", "early termination", "opacity threshold", 0.05, 0.999, false, always,
       [](Perturbed& m, double t) { m.config.termination = t; }, {}, {},
       [](double t) { return fmt::format("early termination at opacity {:.2f}", t); }},
      {"opacity_step_ratio", "opacity corrected for another step", "reference step / sample step", 0.25, 4, true,
       always, [](Perturbed& m, double c) { m.scene.transfer = opacity_scaled(m.scene.transfer, c); }, {}, {},
       [](double c) {
         return fmt::format("opacity corrected with a reference step {:.2f} times the sample distance", c);
       }},
      {"nearest", "nearest-neighbour interpolation", "", 0, 0, false,
       [](const Scene& s, const Camera&) {
         const GridField* g = grid_of(s);
         return g && g->interpolation() == Interpolation::trilinear;
       },
       [](Perturbed& m, double) {
         const GridField g = *grid_of(m.scene);
         m.scene.field = GridField(g.box(), g.resolution(), g.layout(), Interpolation::nearest,
                                   [&](const Vec3& p) { return g.value(p); });
       },
       {}, {}, [](double) { return std::string("nearest-neighbour instead of trilinear interpolation"); }},
      {"box_offset", "volume box offset", "voxels on each side", -1, 1, false, always,
       [](Perturbed& m, double p) {
         const Vec3 d = p * voxel(m.scene);
         m.scene.box.min -= d;
         m.scene.box.max += d;
       },
       {}, {},
       [](double p) {
         return fmt::format("volume box {:.2f} voxel {} on each side{}", std::abs(p), p > 0 ? "larger" : "smaller",
                            std::abs(p - 0.5) < 0.1 ? " (cell- instead of node-centred)" : "");
       }},
      {"tf_bits", "transfer-function table bit depth", "bits", 4, 12, false,
       [](const Scene& s, const Camera&) { return domain_range(s.transfer) > 0; },
       [](Perturbed& m, double b) {
         m.scene.transfer = quantised_table(m.scene.transfer, kQuantisedEntries, static_cast<int>(std::lround(b)));
       },
       {}, {},
       [](double b) {
         return fmt::format("transfer function from a {}-entry table stored in {} bits (values rounded to 1/{:g} "
                            "of their largest)", kQuantisedEntries, std::lround(b), std::ldexp(1.0, static_cast<int>(std::lround(b))) - 1);
       },
       {}, true},
      {"pixel_shift", "pixel-centre shift", "pixels (both axes)", -1, 1, false,
       [](const Scene&, const Camera& c) { return c.projection != Projection::fan; }, {}, {}, {},
       [](double p) {
         return fmt::format("rays {:+.2f} pixel off the pixel centres on both axes{}", p,
                            std::abs(std::abs(p) - 0.5) < 0.1 ? " (through pixel corners: the half-pixel shift)" : "");
       },
       [](const Camera& c, long i, double p) {
         return c.ray_at(static_cast<double>(i % c.width) + 0.5 + p, static_cast<double>(i / c.width) + 0.5 + p);
       }},
  };
  return kEntries;
}

// vrv's model cast along the entry's own rays at `pixels`.
std::vector<double> cast_rays(const Perturbed& m, const std::vector<long>& pixels,
                              const std::function<Ray(long)>& ray) {
  return visit_field(m.scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    const DiscreteRaycaster<F> caster = scene_raycaster(field, m.scene, m.config);
    return image_loop(m.camera, pixels, [&](const Ray&, long pixel) { return caster.cast(ray(pixel)).value; });
  });
}

// The image's values at `pixels` (comparable with vrv's casts).
std::vector<double> observed(const ImageWithStep& image, int channel, const Scene& scene, AlphaMode alpha,
                             const std::vector<long>& pixels) {
  std::vector<double> u;
  for (long i : pixels)
    u.push_back(comparable(image.image, channel, static_cast<std::size_t>(i), scene.background, alpha));
  return u;
}

// The values an entry's renderer shows at `pixels`, with parameter p.
std::vector<double> predict(const Entry& e, const FitInput& in, const std::vector<long>& pixels, double p) {
  Perturbed m{in.scene, in.camera, in.model};
  if (e.perturb) e.perturb(m, p);
  std::vector<long> rays = pixels;
  if (e.remap)
    for (long& i : rays) i = e.remap(i, in.camera.width, in.camera.height);
  std::vector<double> v = e.ray ? cast_rays(m, rays, [&](long i) { return e.ray(m.camera, i, p); })
                                 : cast_pixels(m.scene, m.camera, m.config, rays);
  if (e.curve)
    for (double& x : v) x = e.curve(x, p);
  return v;
}


double squared_residual(const std::vector<double>& u, const std::vector<double>& v) {
  double ss = 0;
  for (std::size_t j = 0; j < u.size(); ++j)
    if (std::isfinite(u[j])) ss += (u[j] - v[j]) * (u[j] - v[j]);
  return std::isfinite(ss) ? ss : std::numeric_limits<double>::infinity();
}

// Least squares over the bracket: a scan, then Brent's method around the best scanned point.
std::pair<double, double> fit_parameter(const Entry& e, const std::function<double(double)>& ss) {
  std::vector<double> x(kScanPoints), f(kScanPoints);
  for (int k = 0; k < kScanPoints; ++k) {
    const double u = static_cast<double>(k) / (kScanPoints - 1);
    x[k] = e.log_scan ? e.lo * std::pow(e.hi / e.lo, u) : e.lo + (e.hi - e.lo) * u;
    f[k] = ss(x[k]);
  }
  const int best = static_cast<int>(std::min_element(f.begin(), f.end()) - f.begin());
  if (e.integer) return {x[best], f[best]};  // the scan is every whole value: nothing between to refine
  std::uintmax_t iterations = kBrentIterations;
  const auto [p, value] = boost::math::tools::brent_find_minima(ss, x[std::max(best - 1, 0)],
                                                                x[std::min(best + 1, kScanPoints - 1)], kBrentBits,
                                                                iterations);
  return value <= f[best] ? std::pair{p, value} : std::pair{x[best], f[best]};
}

FaultFit fitted(const Entry& e, const FitInput& in, const std::vector<long>& pixels, double ss0) {
  const std::vector<double> u = observed(in.finest, in.channel, in.scene, in.alpha, pixels);
  const auto ss = [&](double p) { return squared_residual(u, predict(e, in, pixels, p)); };
  FaultFit f;
  f.id = e.id, f.name = e.name, f.parameter = e.parameter;
  double residual = 0;
  if (*e.parameter) std::tie(f.value, residual) = fit_parameter(e, ss);
  else residual = ss(kNaN);
  f.explained = 1 - residual / ss0;
  f.pixels = static_cast<long>(pixels.size());
  f.description = e.describe(f.value);
  return f;
}

const Entry& entry(const std::string& id) {
  return *std::find_if(entries().begin(), entries().end(), [&](const Entry& e) { return e.id == id; });
}

// The fraction the fit explains on the diagnosis pixels, at its fitted parameter.
void confirm(FaultFit& f, const FitInput& in, const std::vector<long>& pixels, double ss0) {
  const std::vector<double> u = observed(in.finest, in.channel, in.scene, in.alpha, pixels);
  f.confirmed = 1 - squared_residual(u, predict(entry(f.id), in, pixels, f.value)) / ss0;
  f.confirm_pixels = static_cast<long>(pixels.size());
}

bool stalls(const VerifyReport& rep) {
  return rep.verdict.verdict == Verdict::stalls ||
         std::any_of(rep.faults.begin(), rep.faults.end(),
                     [](const Fault& f) { return f.kind == FaultKind::constant_floor; });
}

// The floor is fitted on top of the model of the renderer's placement and rule: among the models
// whose opacity is corrected and that read the transfer function itself (no table), the one whose differences between successive steps match the
// images' (a step-independent floor cancels in them, the discretisation does not), at the finest
// step.  On the ranking pixels of the kDifferenceImages coarsest images (the cheapest casts, and
// the largest differences).  A shaded scene's models take `gradient`, the scheme the diagnosis
// found nearest (a scheme's error does not cancel in the differences, so they cannot choose it).
std::optional<DiscreteConfig> discretisation_model(const Scene& scene, const Camera& camera,
                                                   const std::vector<const ImageWithStep*>& sorted, int channel,
                                                   const VerifyOptions& opt,
                                                   const std::optional<GradientChoice>& gradient) {
  std::vector<double> steps;
  for (const auto* im : sorted) steps.push_back(im->step);
  const std::vector<long> pixels = ranking_pixels(camera.width, camera.height);
  std::vector<std::vector<double>> u;
  const std::size_t n = std::min(kDifferenceImages, sorted.size());
  for (std::size_t k = 0; k < n; ++k) u.push_back(observed(*sorted[k], channel, scene, opt.alpha, pixels));
  std::optional<Model> best;
  double best_ss = std::numeric_limits<double>::infinity();
  for (Model m : distinct_models(scene, steps, opt)) {
    if (gradient) m = with_gradient(m, *gradient, scene);
    // A table is a detail of the value path, which the catalogue fits: the curves themselves here.
    if (!m.label.opacity_corrected || m.per_step.back().table_size > 0) continue;
    std::vector<std::vector<double>> v;
    for (std::size_t k = 0; k < n; ++k) v.push_back(cast_pixels(scene, camera, m.per_step[k], pixels));
    double ss = 0;
    for (std::size_t k = 0; k + 1 < v.size(); ++k)
      for (std::size_t j = 0; j < pixels.size(); ++j) {
        const double d = (u[k][j] - u[k + 1][j]) - (v[k][j] - v[k + 1][j]);
        if (std::isfinite(d)) ss += d * d;
      }
    if (ss < best_ss) best_ss = ss, best = m;
  }
  if (!best) return std::nullopt;
  return best->per_step.back();
}

}  // namespace

std::vector<std::string> fault_fit_ids() {
  std::vector<std::string> ids;
  for (const Entry& e : entries()) ids.emplace_back(e.id);
  return ids;
}

std::vector<FaultFit> fit_faults(const FitInput& in) {
  const std::vector<long> coarse = ranking_pixels(in.camera.width, in.camera.height);
  const std::vector<long> fine = diagnosis_pixels(in.camera.width, in.camera.height);
  const auto unperturbed = [&](const std::vector<long>& pixels) {
    return squared_residual(observed(in.finest, in.channel, in.scene, in.alpha, pixels),
                            cast_pixels(in.scene, in.camera, in.model, pixels));
  };
  const double ss0 = unperturbed(coarse);
  std::vector<FaultFit> fits;
  if (!(ss0 > 0)) return fits;
  for (const Entry& e : entries())
    if (e.applies(in.scene, in.camera)) fits.push_back(fitted(e, in, coarse, ss0));
  const auto by = [](double FaultFit::*field) {
    return [field](const FaultFit& a, const FaultFit& b) { return a.*field > b.*field; };
  };
  std::stable_sort(fits.begin(), fits.end(), by(&FaultFit::explained));
  const double ss0_fine = unperturbed(fine);
  const std::size_t leaders = std::min(kConfirmedFits, fits.size());
  for (std::size_t k = 0; k < leaders; ++k) confirm(fits[k], in, fine, ss0_fine);
  std::stable_sort(fits.begin(), fits.begin() + static_cast<long>(leaders), by(&FaultFit::confirmed));
  return fits;
}

void decompose_floor(VerifyReport& rep, const Scene& scene, const std::vector<const ImageWithStep*>& sorted,
                     int channel, const VerifyOptions& opt) {
  if (!opt.diagnose || sorted.size() < 2 || !stalls(rep)) return;
  const std::optional<GradientChoice> gradient =
      rep.diagnosis.empty() ? std::nullopt : rep.diagnosis.front().gradient_choice;
  const std::optional<DiscreteConfig> model = discretisation_model(scene, rep.camera, sorted, channel, opt, gradient);
  if (!model) return;
  rep.fault_fits = fit_faults({scene, rep.camera, *model, *sorted.back(), channel, opt.alpha});
  if (rep.fault_fits.empty() || !(rep.fault_fits.front().confirmed >= kNamedFraction)) return;
  const FaultFit& f = rep.fault_fits.front();
  std::string evidence = fmt::format("{} ({}): {}: explains {:.0f} % of the error against vrv's nearest model "
                                     "({} pixels; fitted on {})", sorted.back()->name, rep.verdict_channel,
                                     f.description, 100 * f.confirmed, f.confirm_pixels, f.pixels);
  if (rep.fault_fits.size() > 1)
    evidence += fmt::format("; next: {}, {:.0f} %", rep.fault_fits[1].description,
                            100 * (std::isfinite(rep.fault_fits[1].confirmed) ? rep.fault_fits[1].confirmed
                                                                              : rep.fault_fits[1].explained));
  rep.faults.push_back(Fault{FaultKind::fitted, evidence, f.description, kNaN});
}

}  // namespace vrv
