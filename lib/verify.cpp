#include "lib/verify.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/discrete_raycast.h"
#include "lib/util/checksum.h"
#include "lib/util/parallel.h"
#include "lib/util/progress.h"
#include "lib/reference_integrator.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// Reference image and its cache

std::string camera_text(const Camera& c) {
  return fmt::format("camera {} eye {:.17g} {:.17g} {:.17g} target {:.17g} {:.17g} {:.17g} up {:.17g} "
                     "{:.17g} {:.17g} fov {:.17g} extent {:.17g} angle {:.17g} size {} x {}",
                     to_string(c.projection), c.eye[0], c.eye[1], c.eye[2], c.target[0], c.target[1],
                     c.target[2], c.up[0], c.up[1], c.up[2], c.fov_degrees, c.extent, c.angle_degrees,
                     c.width, c.height);
}

// CRC-64 of the key (lib/util/checksum.h).  The file also stores the whole key, compared on
// reading, so a collision cannot return another scene's reference.
std::string cache_name(const std::string& key) { return fmt::format("reference-{}.bin", crc64_hex(key)); }

// Version 2 ends with the CRC-64 of everything before it (lib/util/checksum.h): a file whose
// values were changed (the verdict flipped before) or cut is recomputed, never used.
constexpr std::string_view kCacheMagic = "vrv reference cache 2\n";

// The file's bytes when it is a whole cache entry for `key` with w x h pixels.  A missing file is
// a plain miss; any other is said in one stderr line, and recomputed and rewritten by the caller.
std::optional<std::string> cache_entry(const fs::path& file, const std::string& key, int w, int h) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  const std::string bytes = text.str();
  const std::size_t key_end = kCacheMagic.size() + sizeof(std::uint64_t) + key.size();
  const std::size_t crc_at = key_end + 3 * sizeof(double) * static_cast<std::size_t>(w) * h;
  const auto recompute = [&](std::string_view why) {
    std::cerr << fmt::format("vrv: the reference cache {} {}; recomputing it\n", file.string(), why);
    return std::nullopt;
  };
  if (!bytes.starts_with(kCacheMagic) || bytes.size() != crc_at + sizeof(std::uint64_t) ||
      bytes.compare(key_end - key.size(), key.size(), key) != 0)
    return recompute("is not this reference's (another vrv version, key or image size)");
  std::uint64_t crc = 0;
  std::memcpy(&crc, bytes.data() + crc_at, sizeof crc);
  if (crc != crc64(std::string_view(bytes).substr(0, crc_at))) return recompute("fails its checksum (changed or damaged)");
  return bytes;
}

std::optional<ReferenceImage> read_cache(const fs::path& file, const std::string& key, int w, int h) {
  const std::optional<std::string> bytes = cache_entry(file, key, w, h);
  if (!bytes) return std::nullopt;
  ReferenceImage r;
  r.width = w, r.height = h;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  const char* at = bytes->data() + kCacheMagic.size() + sizeof(std::uint64_t) + key.size();
  for (auto* plane : {&r.value, &r.error_estimate, &r.optical_depth}) {
    plane->resize(n);
    std::memcpy(plane->data(), at, n * sizeof(double));
    at += n * sizeof(double);
  }
  r.from_cache = true;
  r.cache_file = file.string();
  return r;
}

void write_cache(const fs::path& file, const std::string& key, const ReferenceImage& r) {
  std::string bytes(kCacheMagic);
  const std::uint64_t key_size = key.size();
  bytes.append(reinterpret_cast<const char*>(&key_size), sizeof key_size);
  bytes += key;
  for (const auto* plane : {&r.value, &r.error_estimate, &r.optical_depth})
    bytes.append(reinterpret_cast<const char*>(plane->data()), plane->size() * sizeof(double));
  const std::uint64_t crc = crc64(bytes);
  bytes.append(reinterpret_cast<const char*>(&crc), sizeof crc);
  write_file_atomically(file, bytes);
}

ReferenceImage render_reference(const Scene& scene, const Camera& camera, double tol, bool progress) {
  ReferenceImage r;
  r.width = camera.width, r.height = camera.height;
  const long n = static_cast<long>(camera.width) * camera.height;
  r.value.resize(n), r.error_estimate.resize(n), r.optical_depth.resize(n);
  Progress bar("reference", n, progress);
  visit_field(scene, [&](const auto& field) {
    parallel_for_index(n, [&](long i) {
      const Ray ray = camera.ray(static_cast<int>(i % camera.width), static_cast<int>(i / camera.width));
      const ReferenceResult v =
          integrate_reference(field, scene.box, scene.transfer, scene.background, ray, {tol});
      r.value[i] = v.value, r.error_estimate[i] = v.error_estimate, r.optical_depth[i] = v.optical_depth;
      bar.advance();
    });
  });
  bar.finish();
  return r;
}

// ---------------------------------------------------------------------------------------------
// Where each pixel's ray goes: hit mask, silhouette band, transfer-function jump crossings, and
// the sensitivities of I to moving the ray's start and end (the half-step offset signature).

enum Region : unsigned char { kOutside, kInterior, kSilhouette, kJump };
constexpr const char* kRegionNames[] = {"outside", "interior", "silhouette", "tf_jump"};

struct PixelGeometry {
  std::vector<unsigned char> hit, region;
  // dI/d(entry shift) and dI/d(exit shift) per hit pixel (0 elsewhere).
  std::vector<double> d_entry, d_exit;
};

std::vector<double> jump_values(const TransferFunction& tf) {
  std::vector<double> v;
  for (double b : tf.breakpoints()) {
    const auto j = tf.jump_at(b);
    if (j.emission > 0 || j.extinction > 0) v.push_back(b);
  }
  return v;
}

PixelGeometry pixel_geometry(const Scene& scene, const Camera& camera, const ReferenceImage& ref,
                             const VerifyOptions& opt) {
  const int w = camera.width, h = camera.height;
  const long n = static_cast<long>(w) * h;
  PixelGeometry g{std::vector<unsigned char>(n), std::vector<unsigned char>(n, kOutside),
                  std::vector<double>(n), std::vector<double>(n)};
  const std::vector<double> jumps = jump_values(scene.transfer);
  std::vector<unsigned char> crosses(n);
  const TransferFunction& tf = scene.transfer;
  visit_field(scene, [&](const auto& field) {
    parallel_for_index(n, [&](long i) {
      const Ray ray = camera.ray(static_cast<int>(i % w), static_cast<int>(i / w));
      const auto iv = clip(ray, scene.box);
      if (!iv || !(iv->t1 > iv->t0)) return;
      g.hit[i] = 1;
      const double f0 = field.value(ray.at(iv->t0)), f1 = field.value(ray.at(iv->t1));
      const double T1 = std::exp(-ref.optical_depth[i]);
      g.d_entry[i] = -tf.emission(f0) + tf.extinction(f0) * ref.value[i];
      g.d_exit[i] = T1 * (tf.emission(f1) - scene.background * tf.extinction(f1));
      if (jumps.empty()) return;
      const int m = std::max(2, opt.jump_samples);
      double prev = f0;
      for (int k = 1; k < m && !crosses[i]; ++k) {
        const double f = field.value(ray.at(iv->t0 + (iv->t1 - iv->t0) * k / (m - 1)));
        for (double v : jumps)
          if ((prev - v) * (f - v) <= 0 && prev != f) crosses[i] = 1;
        prev = f;
      }
    });
  });
  const int band = std::max(0, opt.silhouette_band);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const long i = static_cast<long>(y) * w + x;
      bool edge = false;
      for (int dy = -band; dy <= band && !edge; ++dy)
        for (int dx = -band; dx <= band && !edge; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < w && yy < h && g.hit[static_cast<long>(yy) * w + xx] != g.hit[i])
            edge = true;
        }
      g.region[i] = edge ? kSilhouette : !g.hit[i] ? kOutside : crosses[i] ? kJump : kInterior;
    }
  return g;
}

// ---------------------------------------------------------------------------------------------
// Per-channel errors


void check_inputs(const std::vector<ImageWithStep>& images, const VerifyOptions& opt) {
  if (images.empty()) throw VerifyInputError("no images to verify");
  const ChannelImage& first = images.front().image;
  for (const ImageWithStep& im : images) {
    if (!(im.step > 0) || !std::isfinite(im.step))
      throw VerifyInputError(fmt::format("{}: step {} must be positive and finite", im.name, im.step));
    if (im.image.width != first.width || im.image.height != first.height)
      throw VerifyInputError(fmt::format("{}: size {} x {} differs from {}'s {} x {}", im.name,
                                         im.image.width, im.image.height, images.front().name,
                                         first.width, first.height));
    if (im.image.planes.size() != first.planes.size())
      throw VerifyInputError(fmt::format("{}: {} channels, {} has {}", im.name, im.image.planes.size(),
                                         images.front().name, first.planes.size()));
    for (const ImageWithStep& other : images)
      if (&other != &im && other.step == im.step)
        throw VerifyInputError(fmt::format("{}: step {} repeats {}'s", im.name, im.step, other.name));
    if (opt.allow_nan) continue;
    for (std::size_t c = 0; c < im.image.planes.size(); ++c)
      for (std::size_t i = 0; i < im.image.planes[c].size(); ++i)
        if (!std::isfinite(im.image.planes[c][i]))
          throw VerifyInputError(fmt::format("{}: pixel ({}, {}) channel {} is {}", im.name,
                                             i % im.image.width, i / im.image.width,
                                             im.image.names[c], im.image.planes[c][i]));
  }
  if (!(opt.threshold >= 0)) throw std::invalid_argument("--threshold: must be >= 0");
  if (!(opt.reference_tol > 0) || !std::isfinite(opt.reference_tol))
    throw std::invalid_argument("--tol: must be positive and finite");
  if (opt.expected_order && !std::isfinite(*opt.expected_order))
    throw std::invalid_argument("--expected-order: must be finite");
  for (int n : opt.table_sizes)
    if (n < 2 || n > kMaxTableSize)
      throw std::invalid_argument(fmt::format("table_sizes: {} is not in [2, {}]", n, kMaxTableSize));
}

// The value a channel stands for, comparable with the reference: colour composited over the
// background, or the alpha itself.
double comparable(const ChannelImage& im, int c, std::size_t i, double background, AlphaMode mode) {
  const double v = im.planes[c][i];
  if (im.alpha < 0 || c == im.alpha) return v;
  const double a = im.planes[im.alpha][i];
  return (mode == AlphaMode::straight ? v * a : v) + background * (1 - a);
}

ChannelReport channel_report(const ImageWithStep& im, int c, const ReferenceImage& ref,
                             const PixelGeometry& geo, double background, const VerifyOptions& opt) {
  ChannelReport r;
  r.image = im.name;
  r.channel = im.image.names[c];
  r.step = im.step;
  r.alpha = c == im.image.alpha;
  // An 8- or 16-bit framebuffer saved as float has its integers' floor (effective_quantum).
  r.quantum = effective_quantum(im.image);
  r.floor_max = r.quantum / 2;
  r.floor_rms = r.quantum / std::sqrt(12.0);
  const std::size_t n = ref.value.size();
  r.error.assign(n, std::numeric_limits<float>::quiet_NaN());
  std::vector<double> by_region[4], all;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = comparable(im.image, c, i, background, opt.alpha);
    if (!std::isfinite(v)) {
      ++r.nan_count;
      continue;
    }
    const double truth = r.alpha ? -std::expm1(-ref.optical_depth[i]) : ref.value[i];
    const double e = v - truth;
    r.error[i] = static_cast<float>(e);
    all.push_back(e);
    by_region[geo.region[i]].push_back(e);
  }
  r.regions.push_back({"all", static_cast<long>(all.size()), error_stats(all, opt.threshold)});
  for (int k : {kSilhouette, kInterior, kJump, kOutside})
    if (!by_region[k].empty() || k != kJump)
      r.regions.push_back({kRegionNames[k], static_cast<long>(by_region[k].size()),
                           error_stats(by_region[k], opt.threshold)});
  const double floor = opt.order_metric == Metric::max ? r.floor_max : r.floor_rms;
  r.at_floor = r.quantum > 0 && metric_value(r.all(), opt.order_metric) <= 2 * floor;
  return r;
}

// The order metric of the difference between two images' channel.
double difference_metric(const ChannelImage& a, const ChannelImage& b, int c, double background,
                         const VerifyOptions& opt) {
  std::vector<double> d;
  for (std::size_t i = 0; i < a.planes[c].size(); ++i) {
    const double x = comparable(a, c, i, background, opt.alpha) - comparable(b, c, i, background, opt.alpha);
    if (std::isfinite(x)) d.push_back(x);
  }
  return metric_value(error_stats(d, opt.threshold), opt.order_metric);
}

// ---------------------------------------------------------------------------------------------
// Diagnosis: vrv's own models

struct Model {
  Candidate label;
  std::vector<DiscreteConfig> per_step;  // one per image; empty when a step cannot be expressed
};

std::string rule_opacity(SegmentRule rule, const Scene& scene) {
  const bool oc = scene.transfer.convention() == Convention::opacity_color;
  switch (rule) {
    case SegmentRule::riemann: return "extinction exp(-tau h) per sample";
    case SegmentRule::alpha:
      return oc ? "opacity taken per sample (not corrected to the sample distance)"
                : "opacity 1 - exp(-tau h) for the sample distance";
    case SegmentRule::trapezoid: return "trapezoid in tau and g e^-Phi between samples";
    default: return "exact for g, tau linear between samples (pre-integration)";
  }
}

constexpr std::pair<Strategy, const char*> kPlacements[] = {
    {Strategy::step, "step (first sample half a step in)"},
    {Strategy::vtk, "vtk (first sample one step in, last partial step dropped)"},
    {Strategy::inviwo, "inviwo (step rounded to fit, samples at midpoints)"}};

std::string_view placement_text(Strategy s) {
  for (auto [strategy, text] : kPlacements)
    if (strategy == s) return text;
  return strategy_name(s);
}

// `base` at every step, labelled from its own settings; `opacity` describes its opacity.
Model model(const Scene& scene, const std::vector<double>& steps, const DiscreteConfig& base,
            const std::string& opacity) {
  Model m;
  m.label.placement = std::string(strategy_name(base.sampling.strategy));
  m.label.rule = std::string(segment_rule_name(base.rule));
  m.label.opacity = opacity;
  m.label.name = fmt::format("{} placement, {} rule, {}", placement_text(base.sampling.strategy), m.label.rule, opacity);
  if (base.color == ColorConvention::premultiplied) {
    m.label.color = "premultiplied";
    m.label.name += ", colour premultiplied by the opacity per unit distance";
  }
  if (base.table_size > 0) {
    const bool centred = base.table_lookup == TableLookup::centred;
    m.label.table = fmt::format("{} {}", base.table_size, table_lookup_name(base.table_lookup));
    m.label.name += fmt::format(", transfer function read from {}-entry tables {}", base.table_size,
                                centred ? "at their entries (half-texel centred)"
                                        : "as a plain texture coordinate (no half-texel remap)");
  }
  for (double h : steps) {
    DiscreteConfig c = base;
    c.sampling.step = h;
    c.sampling.dims = scene.dims;
    m.per_step.push_back(c);
  }
  return m;
}

DiscreteConfig placed(Strategy strategy, SegmentRule rule) {
  DiscreteConfig c;
  c.rule = rule;
  c.sampling.strategy = strategy;
  return c;
}

// The opacity for a unit distance L used at every sample, whatever the sample distance h: vrv's
// oversampling without correction (N = L / h samples per unit step, centred so that they sit
// where a plain step-h raycast puts them).  Nothing when some L / h is not whole.
std::optional<Model> uncorrected_unit_model(const Scene& scene, const std::vector<double>& steps,
                                            Strategy strategy, double L) {
  Model m = model(scene, steps, placed(strategy, SegmentRule::alpha),
                  fmt::format("opacity 1 - exp(-tau L) for the unit distance L = {:g}, not corrected "
                              "to the sample distance", L));
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const double N = L / steps[k];
    if (std::abs(N - std::round(N)) > 1e-9 * N || std::round(N) < 1 || N > 65536) return std::nullopt;
    DiscreteConfig& c = m.per_step[k];
    c.sampling.step = L;
    c.oversample = static_cast<int>(std::round(N));
    c.centred_oversamples = c.oversample > 1;
  }
  return m;
}

// vrv's discrete models of a renderer: every placement x segment rule; for opacity/colour
// transfer functions the renderers' convention (opacity per unit distance corrected to the
// sample distance, as vrv export hands it over), also with premultiplied colour; the corrected
// alpha rule with the transfer function read from N-entry tables, with and without half-texel
// centring; and, for emission/extinction, the opacity of a fixed unit distance left uncorrected.
std::vector<Model> models(const Scene& scene, const std::vector<double>& steps, const VerifyOptions& opt) {
  std::vector<Model> out;
  const bool oc = scene.transfer.convention() == Convention::opacity_color;
  for (auto [strategy, text] : kPlacements)
    for (SegmentRule rule : {SegmentRule::riemann, SegmentRule::alpha, SegmentRule::trapezoid,
                             SegmentRule::exact_linear})
      out.push_back(model(scene, steps, placed(strategy, rule), rule_opacity(rule, scene)));
  // The alpha rule as renderers correct it: for emission/extinction that is its own convention.
  DiscreteConfig corrected = placed(Strategy::step, SegmentRule::alpha);
  std::string corrected_text = rule_opacity(SegmentRule::alpha, scene);
  if (oc) {
    corrected.opacity_unit = OpacityUnit::per_unit_distance;
    corrected_text = fmt::format("opacity per unit distance L = {:g} corrected to the sample distance, "
                                 "1 - (1 - a)^(h/L)", scene.transfer.unit_length());
    for (auto [strategy, text] : kPlacements) {
      corrected.sampling.strategy = strategy;
      out.push_back(model(scene, steps, corrected, corrected_text));
      DiscreteConfig premultiplied = corrected;
      premultiplied.color = ColorConvention::premultiplied;
      out.push_back(model(scene, steps, premultiplied, corrected_text));
    }
  }
  for (int size : opt.table_sizes)
    for (TableLookup lookup : {TableLookup::centred, TableLookup::uncentred})
      for (auto [strategy, text] : kPlacements) {
        DiscreteConfig c = corrected;
        c.sampling.strategy = strategy;
        c.table_size = size;
        c.table_lookup = lookup;
        out.push_back(model(scene, steps, c, corrected_text));
      }
  if (!oc) {
    const double L = opt.unit_distance > 0 ? opt.unit_distance : *std::max_element(steps.begin(), steps.end());
    for (Strategy strategy : {Strategy::step, Strategy::inviwo})
      if (auto m = uncorrected_unit_model(scene, steps, strategy, L)) out.push_back(std::move(*m));
  }
  return out;
}

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

std::vector<Candidate> diagnose(const Scene& scene, const Camera& camera,
                                const std::vector<const ImageWithStep*>& sorted, int channel,
                                const VerifyOptions& opt) {
  std::vector<double> steps;
  for (const auto* im : sorted) steps.push_back(im->step);
  const std::vector<long> pixels = diagnosis_pixels(camera.width, camera.height);
  std::vector<Candidate> out;
  std::vector<std::vector<std::vector<double>>> kept;  // the pixels of every model kept, per step
  for (Model& m : models(scene, steps, opt)) {
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

// ---------------------------------------------------------------------------------------------
// Faults the error pattern matches

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

// Correlation of errors between horizontal and vertical neighbours that both lie in `region`s
// interior/jump pixels; near 1 for a discretisation error (smooth), near 0 for per-pixel noise.
double neighbour_correlation(const ChannelReport& r, const PixelGeometry& g, int w, int h) {
  double xy = 0, xx = 0, yy = 0;
  auto inside = [&](long i) {
    return (g.region[i] == kInterior || g.region[i] == kJump) && std::isfinite(r.error[i]);
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

const RegionStats* region(const ChannelReport& r, std::string_view name) {
  for (const RegionStats& s : r.regions)
    if (s.region == name) return &s;
  return nullptr;
}

// The quantisation named in a fault: the integers' (whatever type stored them) or a float's ulp.
std::string quantum_name(double quantum) {
  if (std::abs(quantum * 255 - 1) < 1e-9) return "8-bit (values on multiples of 1/255)";
  if (std::abs(quantum * 65535 - 1) < 1e-9) return "16-bit (values on multiples of 1/65535)";
  return quantum >= 1.0 / 65535 * 0.999 ? "integer" : "float";
}

std::vector<Fault> find_faults(const VerifyReport& rep, const PixelGeometry& g, int channel_count,
                               const VerifyOptions& opt) {
  std::vector<Fault> faults;
  if (rep.channels.empty()) return faults;
  // The first colour channel of the finest image (the images are sorted by decreasing step).
  const std::size_t images = rep.channels.size() / channel_count;
  int colour = 0;
  while (colour < channel_count && rep.channels[colour].alpha) ++colour;
  if (colour == channel_count) colour = 0;
  const ChannelReport& finest = rep.channels[(images - 1) * channel_count + colour];
  const ChannelReport& coarsest = rep.channels[colour];
  const std::string ch = finest.channel;

  if (finest.at_floor)
    faults.push_back({"quantisation", fmt::format("{} ({}): {} error {:.3g} is within twice the "
                                                  "{} quantisation floor {:.3g}: no order below it",
                                                  finest.image, ch, metric_name(opt.order_metric),
                                                  metric_value(finest.all(), opt.order_metric),
                                                  quantum_name(finest.quantum),
                                                  opt.order_metric == Metric::max ? finest.floor_max : finest.floor_rms)});
  // Half-step offset: the errors are the first-order change of I under moving the samples.
  for (const ChannelReport* r : {&coarsest, &finest}) {
    const OffsetFit f = fit_offsets(*r, g);
    if (!(f.explained >= 0.5) || !(std::abs(f.entry) >= 0.3 && std::abs(f.entry) <= 0.7)) continue;
    faults.push_back({"half-step offset",
                      fmt::format("{} ({}): the error is {:.0f} % explained by moving the samples {:+.2f} "
                                  "steps at the entry and {:+.2f} at the exit: the samples sit half a step "
                                  "{} than a midpoint rule puts them", r->image, ch, 100 * f.explained,
                                  f.entry, f.exit, f.entry > 0 ? "later" : "earlier")});
    break;
  }
  // Constant floor: the images agree with each other much better than with the reference.
  for (const OrderReport& o : rep.orders)
    if (o.kind == "reference" && o.channel == ch && o.judgement.verdict == Verdict::stalls) {
      for (const OrderReport& s : rep.orders)
        if (s.kind == "self" && s.channel == ch && !s.errors.empty() && !o.errors.empty() &&
            s.errors.back() < 0.2 * o.errors.back())
          faults.push_back({"constant floor",
                            fmt::format("{}: every image carries an error of {:.3g} ({}) that does not "
                                        "shrink with the step, while the two finest differ by only {:.3g}: "
                                        "a step-independent error (background, transfer function, "
                                        "precision, camera, or a field other than the scene's: a grid "
                                        "of an analytic field, as `vrv export` writes it; verify an "
                                        "export against its scene.toml)", ch, o.errors.back(),
                                        metric_name(opt.order_metric), s.errors.back())});
    }
  // First-order border band.
  const RegionStats* band = region(finest, "silhouette");
  const RegionStats* inner = region(finest, "interior");
  const RegionStats* jump = region(finest, "tf_jump");
  const double inside_rms = std::max(inner ? inner->stats.rms : 0.0, jump ? jump->stats.rms : 0.0);
  if (band && inner && band->pixels > 0 && band->stats.rms > 3 * inside_rms &&
      band->stats.rms > 2 * finest.floor_rms) {
    std::vector<double> steps, errs;
    for (std::size_t k = 0; k < images; ++k) {
      const ChannelReport& r = rep.channels[k * channel_count + colour];
      steps.push_back(r.step);
      errs.push_back(region(r, "silhouette")->stats.rms);
    }
    const OrderFit f = fit_order(steps, errs);
    if (f.order < 1.5)
      faults.push_back({"first-order border band",
                        fmt::format("{} ({}): RMS {:.3g} in the {}-pixel silhouette band against {:.3g} "
                                    "inside, converging there at order {:.3g}: rays that graze the box "
                                    "(entry/exit handling)", finest.image, ch, band->stats.rms,
                                    opt.silhouette_band, inside_rms, f.order)});
  }
  // Jittered start positions: zero-mean noise, uncorrelated between neighbours, and first order
  // (a random fraction of a step); a step rounded per ray also decorrelates neighbours, but at the
  // rule's own (second) order.
  const double corr = neighbour_correlation(finest, g, rep.width, rep.height);
  double order = kNaN;
  for (const OrderReport& o : rep.orders)
    if (o.kind == "reference" && o.channel == ch) order = o.fit.order;
  // Jittered images differ from each other as much as from the reference: under a constant floor
  // (the images agree with each other) the noise-like error is the floor's, not jitter.
  const bool constant_floor = std::any_of(faults.begin(), faults.end(),
                                          [](const Fault& f) { return f.name == "constant floor"; });
  if (!constant_floor && inner && inner->pixels > 16 && inner->stats.rms > 2 * finest.floor_rms && std::isfinite(corr) &&
      std::abs(corr) < 0.3 && std::abs(inner->stats.mean_signed) < 0.5 * inner->stats.rms && order < 1.5)
    faults.push_back({"jitter", fmt::format("{} ({}): interior error RMS {:.3g} with mean {:.3g} and "
                                            "neighbour correlation {:.2f}: zero-mean noise, as from "
                                            "jittered start positions", finest.image, ch,
                                            inner->stats.rms, inner->stats.mean_signed, corr)});
  // Error concentrated at transfer-function jumps.
  if (jump && inner && jump->pixels > 0 && jump->stats.rms > 3 * inner->stats.rms &&
      jump->stats.rms > 2 * finest.floor_rms)
    faults.push_back({"error at transfer-function jumps",
                      fmt::format("{} ({}): RMS {:.3g} on the {} pixels whose rays cross a jump against "
                                  "{:.3g} elsewhere inside", finest.image, ch, jump->stats.rms,
                                  jump->pixels, inner->stats.rms)});
  // Missing opacity correction: nearest model takes the opacity per sample.
  if (rep.diagnosis.size() >= 2) {
    const Candidate& best = rep.diagnosis.front();
    const bool uncorrected = best.opacity.find("not corrected") != std::string::npos;
    double corrected = kNaN;
    for (const Candidate& c : rep.diagnosis)
      if (c.opacity.find("not corrected") == std::string::npos) {
        corrected = c.rms;
        break;
      }
    if (uncorrected && best.rms < 0.3 * corrected)
      faults.push_back({"missing opacity correction",
                        fmt::format("nearest model: {} (RMS {:.3g}); the nearest corrected model is "
                                    "{:.3g} away", best.name, best.rms, corrected)});
  }
  return faults;
}

}  // namespace

ReferenceImage reference_image(const Scene& scene, const Camera& camera, const VerifyOptions& opt) {
  const bool cache = !opt.cache_dir.empty() && !opt.scene_text.empty();
  std::string key;
  fs::path file;
  if (cache) {
    key = fmt::format("vrv reference\nscene\n{}\n{}\ntol {:.17g}\n", opt.scene_text, camera_text(camera),
                      opt.reference_tol);
    file = opt.cache_dir / cache_name(key);
    if (auto r = read_cache(file, key, camera.width, camera.height)) return *r;
  }
  ReferenceImage r = render_reference(scene, camera, opt.reference_tol, opt.progress);
  if (cache) {
    // An optional cache that cannot be written (a full disk) does not fail the computed run.
    std::error_code ec;
    fs::create_directories(opt.cache_dir, ec);
    try {
      write_cache(file, key, r);
      r.cache_file = file.string();
    } catch (const std::runtime_error& e) {
      std::cerr << fmt::format("vrv: the reference cache was not written: {}\n", e.what());
    }
  }
  return r;
}

Camera verify_camera(const Scene& scene, const VerifyOptions& opt, int w, int h) {
  Camera c = opt.camera ? *opt.camera : scene.camera ? *scene.camera : default_camera(scene.box);
  c.width = w, c.height = h;
  try {
    validate(c);
  } catch (const CameraError& e) {
    throw VerifyInputError(fmt::format("camera: {}", e.what()));
  }
  return c;
}

std::vector<double> discrete_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config) {
  std::vector<long> all(static_cast<std::size_t>(camera.width) * camera.height);
  std::iota(all.begin(), all.end(), 0L);
  return cast_pixels(scene, camera, config, all);
}

void apply(const VerifySettings& s, VerifyOptions& o) {
  validate(ReferenceOptions{s.tol});
  if (!(s.order_tolerance > 0)) throw std::invalid_argument("--order-tolerance: must be positive");
  const auto metric = parse_metric(s.order_metric);
  if (!metric || *metric == Metric::fraction_over)
    throw std::invalid_argument(fmt::format("--order-metric: '{}' is not one of max, mean, rms, p99", s.order_metric));
  if (s.unit_distance < 0) throw std::invalid_argument("--unit-distance: must be positive");
  o.reference_tol = s.tol;
  o.order_tolerance = s.order_tolerance;
  o.order_metric = *metric;
  o.unit_distance = s.unit_distance;
}

VerifyReport verify_images(const Scene& scene, const std::vector<ImageWithStep>& images,
                           const VerifyOptions& opt) {
  check_inputs(images, opt);
  std::vector<const ImageWithStep*> sorted;
  for (const ImageWithStep& im : images) sorted.push_back(&im);
  std::stable_sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->step > b->step; });
  VerifyReport rep;
  rep.width = images.front().image.width;
  rep.height = images.front().image.height;
  rep.camera = verify_camera(scene, opt, rep.width, rep.height);
  rep.threshold = opt.threshold;
  rep.order_metric = opt.order_metric;

  const ReferenceImage ref = reference_image(scene, rep.camera, opt);
  ReferenceInfo& info = rep.reference;
  info.tol = opt.reference_tol;
  info.from_cache = ref.from_cache;
  info.cache_file = ref.cache_file;
  for (std::size_t i = 0; i < ref.value.size(); ++i) {
    info.max_error_estimate = std::max(info.max_error_estimate, ref.error_estimate[i]);
    if (!(ref.error_estimate[i] <= opt.reference_tol) || !std::isfinite(ref.value[i])) {
      ++info.missed;
      if (info.missed_pixels.size() < 10)
        info.missed_pixels.emplace_back(static_cast<int>(i % rep.width), static_cast<int>(i / rep.width));
    }
  }
  if (info.missed) {
    std::string where;
    for (auto [x, y] : info.missed_pixels) where += fmt::format(" ({}, {})", x, y);
    rep.failures.push_back(fmt::format("the reference misses its tolerance {:g} at {} pixel(s):{}{} (max "
                                       "estimate {:.3g})", opt.reference_tol, info.missed, where,
                                       info.missed > 10 ? " ..." : "", info.max_error_estimate));
  }
  rep.reference_image.assign(ref.value.begin(), ref.value.end());
  const PixelGeometry geo = pixel_geometry(scene, rep.camera, ref, opt);
  for (std::size_t i = 0; i < geo.hit.size(); ++i) {
    info.hit_pixels += geo.hit[i];
    info.silhouette_pixels += geo.region[i] == kSilhouette;
    info.jump_pixels += geo.region[i] == kJump;
  }

  const int nc = static_cast<int>(images.front().image.planes.size());
  for (const ImageWithStep* im : sorted)
    for (int c = 0; c < nc; ++c) rep.channels.push_back(channel_report(*im, c, ref, geo, scene.background, opt));

  // Orders and verdicts per channel.
  JudgeOptions jo{opt.expected_order, opt.order_tolerance};
  int worst = -1;
  for (int c = 0; c < nc; ++c) {
    OrderReport against;
    against.channel = images.front().image.names[c];
    against.kind = "reference";
    for (std::size_t k = 0; k < sorted.size(); ++k) {
      const ChannelReport& r = rep.channels[k * nc + c];
      if (r.at_floor) continue;  // no order claimed below the quantisation floor
      against.steps.push_back(r.step);
      against.errors.push_back(metric_value(r.all(), opt.order_metric));
    }
    against.fit = fit_order(against.steps, against.errors);
    against.judgement = judge(against.steps, against.errors, against.fit, jo);
    if (against.steps.size() < sorted.size() && against.steps.size() < 2)
      against.judgement.reason += " (the finer images are at their quantisation floor)";
    OrderReport self;
    self.channel = against.channel;
    self.kind = "self";
    for (std::size_t k = 0; k + 1 < sorted.size(); ++k) {
      self.steps.push_back(sorted[k]->step);
      self.errors.push_back(difference_metric(sorted[k]->image, sorted[k + 1]->image, c, scene.background, opt));
    }
    if (!sorted.empty()) {
      std::vector<double> all_steps;
      for (const auto* im : sorted) all_steps.push_back(im->step);
      self.fit = self_convergence_order(all_steps, self.errors);
      self.judgement = judge(self.steps, self.errors, self.fit, jo);
    }
    if (worst < 0 || severity(against.judgement.verdict) > severity(rep.verdict.verdict)) {
      rep.verdict = against.judgement;
      rep.verdict_channel = against.channel;
      worst = c;
    }
    rep.orders.push_back(std::move(against));
    rep.orders.push_back(std::move(self));
  }
  if (opt.expected_order && rep.verdict.verdict != Verdict::converges)
    rep.failures.push_back(fmt::format("expected convergence at order {:g}; channel {} {}: {}",
                                       *opt.expected_order, rep.verdict_channel,
                                       verdict_name(rep.verdict.verdict), rep.verdict.reason));

  if (opt.diagnose) {
    int colour = 0;
    while (colour < nc && colour == images.front().image.alpha) ++colour;
    if (colour < nc) rep.diagnosis = diagnose(scene, rep.camera, sorted, colour, opt);
  }
  rep.faults = find_faults(rep, geo, nc, opt);
  rep.pass = rep.failures.empty();
  return rep;
}

namespace {

nlohmann::ordered_json number(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

nlohmann::ordered_json to_json(const ErrorStats& s) {
  return {{"count", s.count}, {"max", number(s.max)}, {"mean", number(s.mean)}, {"rms", number(s.rms)},
          {"p99", number(s.p99)}, {"fraction_over", number(s.fraction_over)},
          {"mean_signed", number(s.mean_signed)}};
}

nlohmann::ordered_json to_json(const OrderFit& f) {
  return {{"order", number(f.order)}, {"std_error", number(f.std_error)}, {"points", f.points}};
}

}  // namespace

nlohmann::ordered_json to_json(const VerifyReport& rep) {
  nlohmann::ordered_json j;
  j["pass"] = rep.pass;
  j["verdict"] = verdict_name(rep.verdict.verdict);
  j["verdict_channel"] = rep.verdict_channel;
  j["verdict_reason"] = rep.verdict.reason;
  j["failures"] = rep.failures;
  j["threshold"] = rep.threshold;
  j["order_metric"] = metric_name(rep.order_metric);
  j["width"] = rep.width;
  j["height"] = rep.height;
  const ReferenceInfo& r = rep.reference;
  nlohmann::ordered_json missed = nlohmann::ordered_json::array();
  for (auto [x, y] : r.missed_pixels) missed.push_back({x, y});
  j["reference"] = {{"tol", r.tol}, {"max_error_estimate", number(r.max_error_estimate)},
                    {"missed", r.missed}, {"missed_pixels", missed}, {"from_cache", r.from_cache},
                    {"cache_file", r.cache_file}, {"hit_pixels", r.hit_pixels},
                    {"silhouette_pixels", r.silhouette_pixels}, {"tf_jump_pixels", r.jump_pixels}};
  nlohmann::ordered_json ims = nlohmann::ordered_json::array();
  for (const ChannelReport& c : rep.channels) {
    nlohmann::ordered_json regions;
    for (const RegionStats& s : c.regions) regions[s.region] = to_json(s.stats);
    ims.push_back({{"image", c.image}, {"channel", c.channel}, {"step", c.step}, {"alpha", c.alpha},
                   {"nan_count", c.nan_count}, {"quantum", c.quantum}, {"floor_rms", c.floor_rms},
                   {"at_floor", c.at_floor}, {"regions", regions}});
  }
  j["images"] = ims;
  nlohmann::ordered_json orders = nlohmann::ordered_json::array();
  for (const OrderReport& o : rep.orders) {
    nlohmann::ordered_json e = to_json(o.fit);
    e["channel"] = o.channel;
    e["kind"] = o.kind;
    e["verdict"] = verdict_name(o.judgement.verdict);
    e["reason"] = o.judgement.reason;
    e["steps"] = o.steps;
    nlohmann::ordered_json errs = nlohmann::ordered_json::array();
    for (double v : o.errors) errs.push_back(number(v));
    e["errors"] = errs;
    orders.push_back(e);
  }
  j["orders"] = orders;
  nlohmann::ordered_json diag = nlohmann::ordered_json::array();
  for (const Candidate& c : rep.diagnosis)
    diag.push_back({{"name", c.name}, {"placement", c.placement}, {"rule", c.rule}, {"opacity", c.opacity},
                    {"color", c.color}, {"table", c.table}, {"rms", number(c.rms)}, {"max", number(c.max)}});
  j["diagnosis"] = diag;
  nlohmann::ordered_json faults = nlohmann::ordered_json::array();
  for (const Fault& f : rep.faults) faults.push_back({{"name", f.name}, {"evidence", f.evidence}});
  j["faults"] = faults;
  return j;
}

}  // namespace vrv
