// The parts of the visibility study; see parts.h.
#include "studies/visibility/parts.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string_view>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/discrete_raycast.h"
#include "lib/image_loop.h"
#include "lib/io/image_io.h"
#include "lib/util/progress.h"
#include "lib/reference_integrator.h"
#include "lib/work_estimate.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/study_outputs.h"
#include "studies/engine/study_rays.h"
#include "studies/engine/reference_audit.h"
#include "lib/io/table.h"

namespace vrv {
namespace {

void write_captioned(const StudyRun& run, const std::string& stem, const Table& t, const std::string& caption) {
  write_table(run.dir, stem, t, {caption, "tab:visibility-" + stem, {}});
}

StudyCheck at_most(CheckKind kind, std::string name, double value, double bound, std::string detail) {
  return {std::move(name), value, bound, value <= bound, std::move(detail), kind};
}

DiscreteConfig alpha_config(double step) {
  DiscreteConfig c;
  c.rule = SegmentRule::alpha;
  c.sampling.strategy = Strategy::step;
  c.sampling.step = step;
  return c;
}

std::string num(double x) { return fmt::format("{:.17g}", x); }

// One view's numbers as one checkpoint (--resume); a view whose images are written is always
// computed (images are not checkpointed), which gives the same numbers.
ViewCulling culled_view(Checkpoints* checkpoints, const std::string& key, bool with_images,
                        const std::function<ViewCulling()>& compute) {
  if (with_images) return compute();
  ViewCulling v;
  bool fresh = false;
  const std::vector<double> o = checkpointed(checkpoints, key, [&] {
    v = compute();
    fresh = true;
    std::vector<double> out{double(v.nonempty), double(v.samples_all)};
    for (int m = 0; m < kCullMethods; ++m)
      out.insert(out.end(), {double(v.culled[m]), v.max_error[m], v.min_front_opacity[m], double(v.samples[m])});
    return out;
  }, 2 + 4 * kCullMethods);
  if (fresh) return v;
  v.nonempty = static_cast<int>(o.at(0));
  v.samples_all = static_cast<long>(o.at(1));
  for (std::size_t m = 0; m < kCullMethods; ++m) {
    v.culled[m] = static_cast<int>(o.at(2 + 4 * m));
    v.max_error[m] = o.at(3 + 4 * m);
    v.min_front_opacity[m] = o.at(4 + 4 * m);
    v.samples[m] = static_cast<long>(o.at(5 + 4 * m));
  }
  return v;
}

}  // namespace

// alpha' = 1 - (1 - alpha)^k and eq. (3), on the continuous integral (reference integrator,
// optical depth in log space) and on the discrete raycast (alpha rule: transparency = value
// with no emission and background 1); and the product over two halves of the box.
IdentityResult run_identity(const VisibilityStudy& s, const StudyRun& run) {
  const long n = run.quick ? s.identity.quick_rays : s.identity.rays;
  const std::vector<Ray> rays = study_rays(s.scene.box, n, s.identity.seed);
  const GridField& field = std::get<GridField>(s.scene.field);
  const PiecewiseLinear& tau1 = s.scene.transfer.second();
  const PiecewiseLinear& tau2 = s.identity.basis2;
  const TransferFunction tf1 = absorption_only(tau1, 1), tf2 = absorption_only(tau2, 1);
  std::vector<TransferFunction> tf_k, tf_sum;
  for (double k : s.identity.ks) {
    tf_k.push_back(absorption_only(tau1, k));
    tf_sum.push_back(absorption_only(sum(scaled(tau1, k), tau2), 1));
  }
  const Box box = s.scene.box;
  Box left = box, right = box;
  left.max[0] = right.min[0] = 0.5 * (box.min[0] + box.max[0]);
  ReferenceOptions ref{s.identity.reference_tol};
  ref.stop_when_opaque = false;  // the identities need the whole optical depth
  // Both integrals return the optical depth Phi = -log(transparency).
  auto continuous = [&](const TransferFunction& tf, const Box& b, const Ray& ray) {
    const ReferenceResult r = audited_reference(run.audit, field, b, tf, 1.0, ray, ref);
    return r.hit ? r.optical_depth : 0.0;
  };
  const DiscreteConfig cfg = alpha_config(s.identity.step);
  auto discrete = [&](const TransferFunction& tf, const Ray& ray) {
    return -std::log(DiscreteRaycaster<GridField>(field, box, tf, 1.0, cfg).cast(ray).value);
  };
  auto opacity = [](double depth) { return -std::expm1(-depth); };

  // Per ray, the same rows in the same order: (integral, identity) labels, then five numbers per
  // row (k, alpha direct, from depths, from alphas, transparency difference).  One block of rays
  // is one checkpoint (--resume).
  std::vector<std::pair<const char*, const char*>> labels;
  for (std::size_t j = 0; j < s.identity.ks.size(); ++j)
    labels.insert(labels.end(), {{"continuous", "scale"}, {"discrete", "scale"}, {"continuous", "bases"},
                                 {"discrete", "bases"}});
  labels.push_back({"continuous", "halves"});
  constexpr std::size_t kRow = 5;
  const std::size_t width = labels.size() * kRow;
  Progress bar("visibility identities", n, run.progress);
  const std::vector<double> rows = checkpointed_items(run.checkpoints, "identity", n, 16, width, [&](long i, std::span<double> o) {
    const Ray& ray = rays[i];
    const double c[] = {continuous(tf1, box, ray), continuous(tf2, box, ray)};
    const double d[] = {discrete(tf1, ray), discrete(tf2, ray)};
    const double ca[] = {opacity(c[0]), opacity(c[1])}, da[] = {opacity(d[0]), opacity(d[1])};
    std::size_t row = 0;
    auto add = [&](double k, double direct, std::span<const double> depths, std::span<const double> alphas,
                   std::span<const double> ks) {
      double predicted = 0;  // sum k_i Phi_i
      for (std::size_t m = 0; m < ks.size(); ++m) predicted += ks[m] * depths[m];
      const double v[kRow] = {k, opacity(direct), combined_opacity_of_depths(depths, ks), combined_opacity(alphas, ks),
                              std::abs(std::expm1(predicted - direct))};
      std::copy(v, v + kRow, o.begin() + static_cast<std::ptrdiff_t>(kRow * row++));
    };
    for (std::size_t j = 0; j < s.identity.ks.size(); ++j) {
      const double k = s.identity.ks[j];
      const double kk[] = {k, 1.0};
      const auto one = std::span(kk).first(1);
      add(k, continuous(tf_k[j], box, ray), std::span(c).first(1), std::span(ca).first(1), one);
      add(k, discrete(tf_k[j], ray), std::span(d).first(1), std::span(da).first(1), one);
      add(k, continuous(tf_sum[j], box, ray), c, ca, kk);
      add(k, discrete(tf_sum[j], ray), d, da, kk);
    }
    const double halves[] = {continuous(tf1, left, ray), continuous(tf1, right, ray)};
    const double halves_a[] = {opacity(halves[0]), opacity(halves[1])}, ones[] = {1.0, 1.0};
    add(1.0, c[0], halves, halves_a, ones);
  }, [&](long done) { bar.advance(done); });
  bar.finish();

  Table t({"ray", "integral", "identity", "k", "alpha_direct", "alpha_identity", "abs_difference",
           "abs_difference_from_alpha", "transparency_rel_difference"});
  double worst[2] = {0, 0}, worst_alpha[2] = {0, 0}, worst_t[2] = {0, 0};  // continuous, discrete
  for (long i = 0; i < n; ++i)
    for (std::size_t row = 0; row < labels.size(); ++row) {
      const double* r = rows.data() + static_cast<std::size_t>(i) * width + row * kRow;
      const double k = r[0], direct = r[1], from_depths = r[2], from_alphas = r[3], transparency_rel = r[4];
      const double diff = std::abs(direct - from_depths), diff_a = std::abs(direct - from_alphas);
      const bool disc = std::string_view(labels[row].first) == "discrete";
      worst[disc] = std::max(worst[disc], diff);
      worst_alpha[disc] = std::max(worst_alpha[disc], diff_a);
      worst_t[disc] = std::max(worst_t[disc], transparency_rel);
      t.add_row({i, std::string(labels[row].first), std::string(labels[row].second), k, direct, from_depths, diff,
                 diff_a, transparency_rel});
    }
  write_file_atomically(run.dir / "identity.csv", t.to_csv());
  Table sum_t({"integral", "rays", "max_abs_difference", "max_abs_difference_from_alpha",
                "max_transparency_rel_difference", "bound"});
  for (const char* col : {"max_abs_difference", "max_abs_difference_from_alpha", "max_transparency_rel_difference", "bound"})
    sum_t.set_format(col, "{:.2e}");
  sum_t.add_row({std::string("continuous (reference)"), n, worst[0], worst_alpha[0], worst_t[0], s.identity.max_error});
  sum_t.add_row({std::string("discrete (alpha rule)"), n, worst[1], worst_alpha[1], worst_t[1], s.identity.max_error});
  write_captioned(run, "identity_summary", sum_t,
              "$\\alpha' = 1-(1-\\alpha)^k$ and eq.~(3): largest difference over all rays");

  IdentityResult out;
  out.rays = n;
  out.max_difference = std::max(worst[0], worst[1]);
  out.checks.push_back(at_most(CheckKind::regression, "identity continuous", worst[0], s.identity.max_error,
                               "max |alpha - identity from optical depths| (scale by k, sum of bases, two halves), reference"));
  out.checks.push_back(at_most(CheckKind::derived, "identity continuous (transparency)", worst_t[0], s.identity.max_transparency_error,
                               "max relative difference of the transparency, |expm1(sum k_i Phi_i - Phi)|, reference"));
  out.checks.push_back(at_most(CheckKind::derived, "identity discrete (transparency)", worst_t[1], s.identity.max_transparency_error,
                               "max relative difference of the transparency, alpha-rule raycast"));
  out.checks.push_back(at_most(CheckKind::regression, "identity discrete", worst[1], s.identity.max_error,
                               "max |alpha - identity from optical depths| (scale by k, sum of bases), alpha-rule raycast"));
  return out;
}

// The paper's 58.4: samples of constant opacity alpha until the opacity reaches the threshold,
// and the raycast's own count with early termination at that threshold.
SamplesResult run_threshold_samples(const VisibilityStudy& s, const StudyRun& run) {
  const double alpha = s.samples.alpha, A = s.samples.threshold;
  const double l = samples_to_threshold(alpha, A);
  Scene sc;  // the default box [-1, 1]^3; the field does not matter under a constant transfer function
  const double h = (sc.box.max[0] - sc.box.min[0]) / static_cast<double>(s.samples.ray_samples);
  sc.transfer = TransferFunction::opacity_color(PiecewiseLinear({{0.0, alpha}}),
                                                PiecewiseLinear({{0.0, 1.0}}), h);
  const Ray ray{Vec3(-3, 0.01, 0.02), Vec3(1, 0, 0)};
  DiscreteConfig cfg = alpha_config(h);
  const long all = discrete_raycast(sc, ray, cfg).samples;
  cfg.termination = A;
  const long taken = discrete_raycast(sc, ray, cfg).samples;
  const long expected = static_cast<long>(std::ceil(l));

  Table t({"quantity", "ours", "paper"});
  t.allow_missing("paper");
  t.set_format("ours", "{:.6g}");
  t.add_row({std::string("samples to the threshold, log(1-A)/log(1-alpha)"), l, s.samples.paper_samples});
  t.add_row({std::string("samples the raycast takes with early termination"), double(taken), double(expected)});
  t.add_row({std::string("samples without termination"), double(all), std::nan("")});
  t.add_row({fmt::format("opacity after {} samples", expected - 1),
             scaled_opacity(alpha, double(expected - 1)), std::nan("")});
  t.add_row({fmt::format("opacity after {} samples", expected), scaled_opacity(alpha, double(expected)),
             std::nan("")});
  write_captioned(run, "threshold_samples", t,
              fmt::format("Samples of opacity {} until the accumulated opacity reaches {}", alpha, A));

  SamplesResult out;
  out.discrete_samples = taken;
  out.checks.push_back({"58.4 samples", l, s.samples.paper_samples,
                        std::abs(l - s.samples.paper_samples) <= s.samples.paper_rounding,
                        fmt::format("log(1-{})/log(1-{}) equals the paper's number within {} (arithmetic: "
                                    "the paper's number recomputed)", A, alpha, s.samples.paper_rounding),
                        CheckKind::identity});
  out.checks.push_back({"termination sample count", double(taken), double(expected), taken == expected,
                        fmt::format("the alpha-rule raycast stops after ceil(l) samples (of {})", all),
                        CheckKind::derived});
  return out;
}

// Early termination at accumulated opacity A: the rest of the ray, carrying transparency
// T <= 1 - A, could have added at most T * max radiance, so |terminated - full| <= (1 - A) R.
TerminationResult run_termination(const VisibilityStudy& s, const StudyRun& run) {
  Camera cam = s.scene.camera.value_or(default_camera(s.scene.box));
  const long side = run.quick ? s.termination.quick_image : s.termination.image;
  cam.width = cam.height = static_cast<int>(side);
  const long P = side * side;
  const GridField& field = std::get<GridField>(s.scene.field);
  std::vector<double> thresholds = s.termination.thresholds;
  std::sort(thresholds.begin(), thresholds.end());
  const std::size_t m = thresholds.size();
  // Column 0: the reference; 1: no termination; 2 + i: threshold i.
  std::vector<std::vector<double>> value(m + 2, std::vector<double>(P));
  std::vector<std::vector<long>> samples(m + 2, std::vector<long>(P, 0));
  std::vector<DiscreteRaycaster<GridField>> casters;
  DiscreteConfig cfg = alpha_config(s.termination.step);
  casters.emplace_back(field, s.scene.box, s.scene.transfer, s.scene.background, cfg);
  for (double A : thresholds) {
    cfg.termination = A;
    casters.emplace_back(field, s.scene.box, s.scene.transfer, s.scene.background, cfg);
  }
  // Per pixel: the reference, then (value, samples) per caster; one image row is one checkpoint.
  const std::size_t width = 1 + 2 * casters.size();
  Progress bar("visibility termination", P, run.progress);
  ImageLoopHooks hooks;
  hooks.block = cam.width;
  hooks.progress = [&](long done) { bar.advance(done); };
  const std::vector<double> pixels = image_records(cam, {}, width, [&](const Ray& ray, std::span<double> o) {
    o[0] = audited_reference(run.audit, s.scene, ray, {s.termination.reference_tol}).value;
    for (std::size_t c = 0; c < casters.size(); ++c) {
      const DiscreteResult r = casters[c].cast(ray);
      o[1 + 2 * c] = r.value;
      o[2 + 2 * c] = static_cast<double>(r.samples);
    }
  }, hooks, checkpoint_blocks(run.checkpoints, "termination"));
  bar.finish();
  for (long p = 0; p < P; ++p) {
    const double* o = pixels.data() + static_cast<std::size_t>(p) * width;
    value[0][p] = o[0];
    for (std::size_t c = 0; c < casters.size(); ++c) {
      value[c + 1][p] = o[1 + 2 * c];
      samples[c + 1][p] = static_cast<long>(o[2 + 2 * c]);
    }
  }

  auto total = [&](std::size_t c) {
    long n = 0;
    for (long x : samples[c]) n += x;
    return n;
  };
  auto errors = [&](std::size_t c, std::size_t against) {
    double mx = 0, mean = 0;
    for (long p = 0; p < P; ++p) {
      const double e = std::abs(value[c][p] - value[against][p]);
      mx = std::max(mx, e);
      mean += e / static_cast<double>(P);
    }
    return std::pair{mx, mean};
  };
  Table t({"threshold", "one_minus_threshold", "samples", "samples_saved", "max_error", "mean_error",
           "bound", "max_error_reference", "mean_error_reference"});
  t.allow_missing("one_minus_threshold");
  for (const char* c : {"max_error", "mean_error", "bound", "max_error_reference", "mean_error_reference"})
    t.set_format(c, "{:.3e}");
  t.set_format("samples_saved", "{:.4f}");
  Table plot({"one_minus_threshold", "series", "value"});
  TerminationResult out;
  out.side = side;
  const long full = total(1);
  long violations = 0, previous = 0;
  for (std::size_t c = 1; c < m + 2; ++c) {
    const double A = c == 1 ? 1.0 : thresholds[c - 2];
    const auto [mx, mean] = errors(c, 1);
    const auto [rmx, rmean] = errors(c, 0);
    const double bound = (1 - A) * s.radiance;
    const long n = total(c);
    const double om = c == 1 ? std::nan("") : 1 - A;
    t.add_row({A, om, n, 1 - double(n) / double(full), mx, mean, bound, rmx, rmean});
    if (c == 1) continue;
    plot.add_row({om, std::string("max |terminated - full|"), mx});
    plot.add_row({om, std::string("bound (1 - A) R"), bound});
    out.checks.push_back(at_most(CheckKind::derived, fmt::format("termination at {}", A), mx, bound,
                                 "max pixel error against no termination within (1 - A) max(colour, background)"));
    if (c > 2 && n < previous) ++violations;
    previous = n;
  }
  if (total(m + 1) > full) ++violations;
  out.checks.push_back(at_most(CheckKind::derived, "termination samples monotone", double(violations), 0,
                               "samples never fall as the threshold rises, and never exceed no termination"));
  write_captioned(run, "termination", t, "Early ray termination: image error and samples saved");
  write_file_atomically(run.dir / "termination_plot.csv", plot.to_csv());

  // Images: the reference, and the error of termination at the study's threshold (or the nearest).
  auto image = [&](std::size_t c) {
    Image im(static_cast<int>(side), static_cast<int>(side));
    for (long p = 0; p < P; ++p) im.pixels[p] = static_cast<float>(value[c][p]);
    return im;
  };
  const double hi = std::max(1e-12, *std::max_element(value[0].begin(), value[0].end()));
  write_exr(image(0), run.dir / "termination_reference.exr");
  write_png_preview(image(0), run.dir / "termination_reference.png", 0, hi);
  std::size_t pick = 2;
  for (std::size_t i = 0; i < m; ++i)
    if (std::abs(thresholds[i] - s.samples.threshold) < std::abs(thresholds[pick - 2] - s.samples.threshold))
      pick = i + 2;
  Image err(static_cast<int>(side), static_cast<int>(side));
  for (long p = 0; p < P; ++p) err.pixels[p] = static_cast<float>(value[pick][p] - value[1][p]);
  write_exr(err, run.dir / "termination_error_map.exr");
  write_error_map_png(err, run.dir / "termination_error_map.png", (1 - thresholds[pick - 2]) * s.radiance);
  return out;
}

CullingResult run_culling(const VisibilityStudy& s, const StudyRun& run) {
  const auto& c = s.culling;
  const auto views = run.quick ? c.quick_views : c.views;
  CullingResult out;
  out.n_theta = views[0];
  out.n_phi = views[1];
  out.side = run.quick ? c.quick_image : c.image;
  out.bound = (1 - c.threshold) * s.radiance;
  out.pof_block = c.pof_block;
  const GridField& field = std::get<GridField>(s.scene.field);
  const BlockGrid blocks{s.scene.box, c.blocks};
  const BlockExtinction ext = block_extinction(field, s.scene.transfer, blocks);
  CullingOptions o;
  o.threshold = c.threshold;
  o.step = c.step;
  o.chord_fraction = c.chord_fraction;
  o.side = static_cast<int>(out.side);
  // The image view, mapped onto the quick grid.
  const int vi = c.image_view[0] * views[0] / c.views[0], vj = c.image_view[1] * views[1] / c.views[1];
  const int equator = views[1] / 2;
  out.equator_phi_text = num(view_phi_degrees(equator, views[1]));

  std::vector<std::string> cols{"theta", "phi", "nonempty"};
  const std::string suffix[kCullMethods] = {"pof", "chord", "seq"};
  for (const char* what : {"culled", "share_culled", "max_error", "min_front_opacity", "samples"})
    for (int m = 0; m < kCullMethods; ++m) cols.push_back(fmt::format("{}_{}", what, suffix[m]));
  cols.push_back("samples_all");
  Table t(cols);
  Table lng({"theta", "phi", "method", "share_culled", "max_error"});
  Table pof_t({"theta", "phi", "min_opacity"});
  std::array<double, kCullMethods> min_front{1, 1, 1}, err{}, share{};
  std::array<long, kCullMethods> culled{}, used{};
  long nonempty = 0, used_all = 0;
  const int nv = views[0] * views[1];
  Progress bar("visibility culling", nv, run.progress);
  for (int j = 0; j < views[1]; ++j)
    for (int i = 0; i < views[0]; ++i) {
      const Vec3 d = view_direction(i, j, views[0], views[1]);
      const double chord = credited_chord(blocks.size(), d, c.chord_fraction);
      std::vector<double> pof(blocks.count());
      for (int b = 0; b < blocks.count(); ++b) pof[b] = pof_depth(ext.tau_min[b], chord, c.step);
      const ViewCulling v = culled_view(run.checkpoints, fmt::format("view_{}_{}", i, j), i == vi && j == vj,
                                        [&] { return cull_view(s.scene, field, blocks, ext, pof, d, o); });
      const double theta = view_theta_degrees(i, views[0]), phi = view_phi_degrees(j, views[1]);
      std::array<double, kCullMethods> sh{};
      for (int m = 0; m < kCullMethods; ++m) sh[m] = v.nonempty ? double(v.culled[m]) / v.nonempty : 0;
      t.add_row({theta, phi, long(v.nonempty), long(v.culled[0]), long(v.culled[1]), long(v.culled[2]), sh[0], sh[1],
                 sh[2], v.max_error[0], v.max_error[1], v.max_error[2], v.min_front_opacity[0],
                 v.min_front_opacity[1], v.min_front_opacity[2], v.samples[0], v.samples[1], v.samples[2],
                 v.samples_all});
      for (int m = 0; m < kCullMethods; ++m) {
        lng.add_row({theta, phi, std::string(kCullMethodNames[m]), sh[m], v.max_error[m]});
        min_front[m] = std::min(min_front[m], v.min_front_opacity[m]);
        err[m] = std::max(err[m], v.max_error[m]);
        culled[m] += v.culled[m];
        used[m] += v.samples[m];
        share[m] += sh[m] / nv;
      }
      pof_t.add_row({theta, phi, -std::expm1(-pof[c.pof_block])});
      nonempty += v.nonempty;
      used_all += v.samples_all;
      if (i == vi && j == vj) {
        write_exr(v.image_all, run.dir / "culling_all.exr");
        const float hi = std::max(1e-12f, *std::max_element(v.image_all.pixels.begin(), v.image_all.pixels.end()));
        write_png_preview(v.image_all, run.dir / "culling_all.png", 0, hi);
        for (int m : {kPof, kSequential}) {
          write_png_preview(v.image[m], run.dir / fmt::format("culling_{}.png", suffix[m]), 0, hi);
          Image e(v.image_all.width, v.image_all.height);
          for (std::size_t p = 0; p < e.pixels.size(); ++p) e.pixels[p] = v.image[m].pixels[p] - v.image_all.pixels[p];
          write_error_map_png(e, run.dir / fmt::format("culling_{}_error.png", suffix[m]), out.bound);
        }
      }
      bar.advance();
    }
  bar.finish();
  out.max_error = *std::max_element(err.begin(), err.end());
  out.mean_share_pof = share[kPof];
  out.mean_share_chord = share[kChord];
  out.mean_share_seq = share[kSequential];
  write_file_atomically(run.dir / "culling.csv", t.to_csv());
  write_file_atomically(run.dir / "culling_long.csv", lng.to_csv());
  write_file_atomically(run.dir / "pof.csv", pof_t.to_csv());

  Table sum_t({"method", "views", "nonempty_blocks", "culled_share", "mean_view_share", "samples_saved",
               "max_error", "bound", "min_front_opacity"});
  for (const char* col : {"culled_share", "mean_view_share", "samples_saved", "min_front_opacity"})
    sum_t.set_format(col, "{:.4f}");
  sum_t.set_format("max_error", "{:.3e}");
  sum_t.set_format("bound", "{:.3e}");
  const double ne = double(std::max(nonempty, 1L));
  const std::string label[kCullMethods] = {"POF table", "chord bound per pixel", "sequential (rendered opacity)"};
  for (int m = 0; m < kCullMethods; ++m)
    sum_t.add_row({label[m], long(nv), nonempty, culled[m] / ne, share[m], 1 - double(used[m]) / double(used_all),
                   err[m], out.bound, min_front[m]});
  write_captioned(run, "culling_summary", sum_t,
              fmt::format("Block culling at threshold {} over {} views (non-empty blocks summed over views)",
                          c.threshold, nv));

  for (int m = 0; m < kCullMethods; ++m) {
    out.checks.push_back(at_most(CheckKind::derived, fmt::format("culling {} error", kCullMethodNames[m]), err[m], out.bound,
                                 "max pixel error of culling within (1 - threshold) max(colour, background)"));
    // Sequential culling culls exactly when the same depth buffer reaches the threshold, so its
    // check holds by construction; POF and chord culling predict the opacity from tables.
    const bool sequential = m == kSequential;
    out.checks.push_back({fmt::format("culling {} conservative", kCullMethodNames[m]), min_front[m], c.threshold,
                          min_front[m] >= c.threshold,
                          sequential ? "least rendered opacity in front of a culled block reaches the threshold "
                                       "(by construction: it culls on that opacity)"
                                     : "least rendered opacity in front of a culled block reaches the threshold",
                          sequential ? CheckKind::identity : CheckKind::derived});
  }
  out.checks.push_back({"POF culls", double(culled[kPof]), 0, culled[kPof] > 0,
                        "POF culling removes some blocks (the check is not vacuous)", CheckKind::derived});
  return out;
}

StudyWork visibility_work(const VisibilityStudy& s, bool quick) {
  const Scene& scene = s.scene;
  StudyWork work;
  // Identities: per ray the two bases, per k the scaled and the summed one, both by the reference
  // and by the raycast; and the two halves (reference) -- the whole ray each time (no early stop).
  const double ks = static_cast<double>(s.identity.ks.size());
  work.add("identities", static_cast<double>(quick ? s.identity.quick_rays : s.identity.rays),
           (4 + 2 * ks) * reference_evaluations(scene, s.identity.reference_tol) +
               (2 + 2 * ks) * discrete_samples(alpha_config(s.identity.step), scene));
  work.add("58.4 samples", 2, static_cast<double>(s.samples.ray_samples));  // with and without termination
  const double side = static_cast<double>(quick ? s.termination.quick_image : s.termination.image);
  work.add("early termination", side * side,
           reference_evaluations(scene, s.termination.reference_tol) +
               static_cast<double>(1 + s.termination.thresholds.size()) *
                   discrete_samples(alpha_config(s.termination.step), scene));
  // Culling: every view's pixels are sampled once, then composited per method from the samples.
  const auto& views = quick ? s.culling.quick_views : s.culling.views;
  const double cside = static_cast<double>(quick ? s.culling.quick_image : s.culling.image);
  work.add("culling views", double(views[0]) * views[1] * cside * cside,
           discrete_samples(alpha_config(s.culling.step), scene));
  return work;
}

}  // namespace vrv
