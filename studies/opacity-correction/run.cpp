// The opacity-correction study's run: each part of Lee & Newman (WSCG 2007) in turn, its table
// (CSV, Markdown, LaTeX), images and plots, and the checks the study states.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/metrics.h"
#include "lib/work_estimate.h"
#include "studies/engine/study_rays.h"
#include "lib/io/table.h"
#include "studies/engine/study_outputs.h"
#include "studies/opacity-correction/opacity_correction.h"

namespace vrv {
namespace {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

void write_captioned(const std::filesystem::path& dir, const std::string& stem, const Table& t, const std::string& caption) {
  write_table(dir, stem, t, {caption, "tab:opacity-" + stem, {}});
}

StudyCheck at_most(CheckKind kind, std::string name, double value, double bound, std::string detail) {
  return {std::move(name), value, bound, value <= bound, std::move(detail), kind};
}

StudyCheck holds(CheckKind kind, std::string name, bool ok, std::string detail) {
  return {std::move(name), ok ? 1.0 : 0.0, 1.0, ok, std::move(detail), kind};
}

std::string read_loadavg() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return in ? a + " " + b + " " + c : std::string("unknown");
}

bool has_q(const OpacityStudy& s) {
  return std::find(s.corrections.begin(), s.corrections.end(), Correction::lee_newman_quadratic) != s.corrections.end();
}

std::string name_of(Correction c) { return std::string(correction_name(c)); }

double paper_or_missing(const std::map<Correction, double>& m, Correction c) {
  const auto it = m.find(c);
  return it == m.end() ? kMissing : it->second;
}

// Fig. 4: one voxel, unit sample against N oversamples, per correction.
void voxel_part(const OpacityStudy& s, const StudyRun& run, StudyOutcome& out) {
  const int N = static_cast<int>(s.oversamples.size());
  std::vector<double> a;
  for (double d : s.oversamples) a.push_back(d / s.scale);
  const double unit = s.unit / s.scale;
  Table t({"correction", "N", "opacity", "intensity", "p"});
  t.allow_missing("p");
  for (const char* c : {"opacity", "intensity", "p"}) t.set_format(c, "{:.6f}");
  t.add_row({std::string("unit sampling"), 1L, unit, unit * unit, kMissing});
  std::map<Correction, GroupResult> r;
  for (Correction c : s.corrections) {
    r[c] = composite_group(c, a, a, N);
    const bool lee = c == Correction::lee_newman || c == Correction::lee_newman_quadratic;
    t.add_row({name_of(c), static_cast<long>(N), r[c].opacity, r[c].intensity, lee ? r[c].p : kMissing});
  }
  write_captioned(run.dir, "voxel", t, "Fig.~4: one voxel, resultant opacity and intensity ($\\alpha = C = D/255$)");
  out.checks.push_back(at_most(CheckKind::identity, "Fig. 4: lee_newman opacity = unit opacity", std::fabs(r[Correction::lee_newman].opacity - unit),
                               s.b_identity, "|composited opacity - D_unit/255|: eq. 9 by construction"));
  out.checks.push_back(holds(CheckKind::derived, "Fig. 4: none over-composites", r[Correction::none].opacity > unit && r[Correction::none].intensity > unit * unit,
                             "uncorrected opacity and intensity above the unit sample's (paper's behaviour 1)"));
  out.checks.push_back(holds(CheckKind::derived, "Fig. 4: corrections limit over-composition",
                             r[Correction::lacroute].opacity < r[Correction::none].opacity &&
                                 r[Correction::lee_newman].opacity < r[Correction::none].opacity &&
                                 r[Correction::lacroute].intensity < r[Correction::none].intensity &&
                                 r[Correction::lee_newman].intensity < r[Correction::none].intensity,
                             "lacroute and lee_newman opacity and intensity below none's (paper's behaviour 2)"));
}

// Image with the second sample's code b growing upwards (row 0 = b = 255), x = first sample's a.
Image surface_image(const std::vector<double>& v) {
  Image im(256, 256);
  for (int b = 0; b < 256; ++b)
    for (int a = 0; a < 256; ++a) im.at(a, 255 - b) = static_cast<float>(v[b * 256 + a]);
  return im;
}

// Fig. 3: all 8-bit pairs, N = 2.
void surfaces_part(const OpacityStudy& s, const StudyRun& run, StudyOutcome& out) {
  std::map<Correction, PairSurface> surf;
  for (Correction c : s.corrections) surf.emplace(c, pair_surface(c));
  Table t({"correction", "a", "b", "opacity", "intensity"});
  for (Correction c : s.corrections) {
    const PairSurface& p = surf.at(c);
    for (int b = 0; b < 256; b += static_cast<int>(s.csv_stride))
      for (int a = 0; a < 256; a += static_cast<int>(s.csv_stride))
        t.add_row({name_of(c), static_cast<long>(a), static_cast<long>(b), p.opacity[b * 256 + a], p.intensity[b * 256 + a]});
    write_exr(surface_image(p.opacity), run.dir / fmt::format("surface_opacity_{}.exr", name_of(c)));
    write_png_preview(surface_image(p.opacity), run.dir / fmt::format("surface_opacity_{}.png", name_of(c)), 0, 1);
    write_exr(surface_image(p.intensity), run.dir / fmt::format("surface_intensity_{}.exr", name_of(c)));
    write_png_preview(surface_image(p.intensity), run.dir / fmt::format("surface_intensity_{}.png", name_of(c)), 0, 1);
  }
  write_file_atomically(run.dir / "surfaces.csv", t.to_csv());
  // The new correction against the prior one, signed, with a colour bar.
  const PairSurface &lac = surf.at(Correction::lacroute), &lee = surf.at(Correction::lee_newman);
  for (const char* q : {"opacity", "intensity"}) {
    const bool op = std::string(q) == "opacity";
    std::vector<double> d(256 * 256);
    double m = 0;
    for (int i = 0; i < 256 * 256; ++i) {
      d[i] = op ? lee.opacity[i] - lac.opacity[i] : lee.intensity[i] - lac.intensity[i];
      m = std::max(m, std::fabs(d[i]));
    }
    write_exr(surface_image(d), run.dir / fmt::format("surface_{}_lee_newman_minus_lacroute.exr", q));
    write_error_map_png(surface_image(d), run.dir / fmt::format("surface_{}_lee_newman_minus_lacroute.png", q), m);
  }
  // Identities over all 65536 pairs.
  double lee_id = 0, lac_diag = 0, none_id = 0, quad = 0;
  const PairSurface& none = surf.at(Correction::none);
  for (int b = 0; b < 256; ++b)
    for (int a = 0; a < 256; ++a) {
      const int i = b * 256 + a;
      const double x = a / 255.0, y = b / 255.0;
      lee_id = std::max(lee_id, std::fabs(lee.opacity[i] - x));
      if (a == b) lac_diag = std::max(lac_diag, std::fabs(lac.opacity[i] - x));
      none_id = std::max(none_id, std::fabs(none.opacity[i] - (x + y - x * y)));
      const double g[2] = {x, y};
      quad = std::max(quad, std::fabs(lee_newman_quadratic_p(g, x) - lee_newman_p(g, x)));
    }
  out.checks.push_back(at_most(CheckKind::identity, "Fig. 3: lee_newman opacity = first sample's", lee_id, s.b_identity,
                               "max over 256^2 pairs |opacity - a/255| (eq. 9)"));
  out.checks.push_back(at_most(CheckKind::identity, "Fig. 3: lacroute exact on homogeneous pairs", lac_diag, s.b_identity,
                               "max over a = b |opacity - a/255| (eq. 5)"));
  out.checks.push_back(at_most(CheckKind::identity, "Fig. 3: none opacity = 1 - (1-a)(1-b)", none_id, s.b_identity, "max over 256^2 pairs"));
  out.checks.push_back(at_most(CheckKind::identity, "quadratic fit exact at N = 2", quad, s.b_quadratic,
                               "max over 256^2 pairs |p_quadratic - p_exact| (eq. 10 is quadratic)"));
}

void add_fit_row(Table& t, const std::string& set, int N, const FitErrorStats& f) {
  t.add_row({set, static_cast<long>(N), f.groups, f.mean, f.sd, f.fraction_above, f.max});
}

// Sec. 4.4: |p_quadratic - p_exact|.
void fit_part(const OpacityStudy& s, const StudyRun& run, StudyOutcome& out) {
  Table t({"set", "N", "groups", "mean", "sd", "fraction_above", "max"});
  t.allow_missing("groups");
  t.allow_missing("max");
  for (const char* c : {"mean", "sd", "max"}) t.set_format(c, "{:.4g}");
  t.set_format("fraction_above", "{:.4g}");
  bool in_unit = true;
  double mean5 = kMissing;
  const long count = run.quick ? s.fit_quick_groups : s.fit_groups;
  for (int N : s.fit_N) {
    const FitErrorStats f = fit_error_stats(random_byte_groups(N, count, s.fit_seed), N, s.threshold);
    in_unit = in_unit && f.all_in_unit;
    if (N == 5) mean5 = f.mean;
    add_fit_row(t, "random 8-bit", N, f);
  }
  const FitErrorStats ramps = fit_error_stats(ramp_groups(5), 5, s.threshold);
  add_fit_row(t, "8-bit linear ramps", 5, ramps);
  Camera cam = s.camera;
  if (run.quick) cam.width = s.quick_width, cam.height = s.quick_height;
  const FitErrorStats rendered = fit_error_stats(render_groups(s.scenes, cam, s.render_N, false), s.render_N, s.threshold);
  add_fit_row(t, fmt::format("ML render groups ({}x{})", cam.width, cam.height), s.render_N, rendered);
  t.add_row({std::string("paper: lobster CT 120x120x34"), 5L, kMissing, 0.0031, 0.012, 0.0009, kMissing});
  write_captioned(run.dir, "fit", t, "Sec.~4.4: $|p_\\mathrm{quadratic} - p_\\mathrm{exact}|$");
  out.checks.push_back(holds(CheckKind::derived, "fit: every p_quadratic in [0, 1]", in_unit && ramps.all_in_unit && rendered.all_in_unit,
                             "finite and in [0, 1] on every set"));
  if (!std::isnan(mean5))
    out.checks.push_back(at_most(CheckKind::regression, "fit: mean error, random 8-bit, N = 5", mean5, s.b_fit_mean, "paper (lobster): 0.0031"));
  out.parameters["fit_render_groups"] = rendered.groups;
}

std::string placement_name(bool centred) { return centred ? "centred" : "first"; }

// The q-quantile of |values|: an error map's colour range that the silhouette pixels (grazing
// rays the step strategy misses, a few per cent of the image) do not wash out; larger values
// are clamped.
double quantile_abs(std::vector<double> v, double q) {
  for (double& x : v) x = std::fabs(x);
  if (v.empty()) return 0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

// Fig. 7: the oversampled render of the grid against the analytic integral, per pixel.
std::map<Correction, double> render_part(const OpacityStudy& s, const StudyRun& run, StudyOutcome& out) {
  Camera cam = s.camera;
  if (run.quick) cam.width = s.quick_width, cam.height = s.quick_height;
  std::vector<RenderMethod> methods{{"unit sampling", Correction::none, 1, false}};
  for (bool centred : s.placements)
    for (Correction c : s.corrections)
      methods.push_back({name_of(c) + (centred ? ", centred" : ""), c, s.render_N, centred});
  const RenderValues v = render_values(s.scenes, cam, methods, run.progress, run.checkpoints, run.audit);
  Table t({"method", "correction", "placement", "N", "mean_abs_difference", "max_abs_difference", "rms_difference",
           "paper"});
  t.allow_missing("paper");
  for (const char* c : {"mean_abs_difference", "max_abs_difference", "rms_difference", "paper"}) t.set_format(c, "{:.4f}");
  std::vector<std::vector<double>> diff;
  double scale = 0;
  long nonfinite = 0;
  for (double x : v.reference) nonfinite += !std::isfinite(x);
  for (std::size_t k = 0; k < methods.size(); ++k) {
    std::vector<double> d(v.reference.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
      nonfinite += !std::isfinite(v.methods[k][i]);
      d[i] = v.methods[k][i] - v.reference[i];
    }
    // Schulze's colours are far off (plain colours scaled again, docs/opacity-correction.md): it
    // would wash out the others' maps, so it is clamped at their range instead.
    if (methods[k].correction != Correction::schulze) scale = std::max(scale, quantile_abs(d, s.error_map_quantile));
    diff.push_back(std::move(d));
  }
  write_exr(to_image(v.reference, cam.width, cam.height), run.dir / "render_reference.exr");
  write_png_preview(to_image(v.reference, cam.width, cam.height), run.dir / "render_reference.png", 0, 1);
  std::map<std::pair<bool, Correction>, double> mean;
  double unit_mean = 0;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const RenderMethod& m = methods[k];
    const ErrorStats st = pixel_difference(v.methods[k], v.reference);
    const std::string stem = m.N == 1 ? "unit" : name_of(m.correction) + (m.centred ? "_centred" : "");
    const bool paper_row = m.N != 1 && !m.centred;
    t.add_row({m.label, name_of(m.correction), m.N == 1 ? std::string("-") : placement_name(m.centred),
               static_cast<long>(m.N), st.mean, st.max, st.rms,
               paper_row ? paper_or_missing(s.paper_render, m.correction) : kMissing});
    if (m.N == 1) unit_mean = st.mean;
    else mean[{m.centred, m.correction}] = st.mean;
    write_exr(to_image(v.methods[k], cam.width, cam.height), run.dir / fmt::format("render_{}.exr", stem));
    write_png_preview(to_image(v.methods[k], cam.width, cam.height), run.dir / fmt::format("render_{}.png", stem), 0, 1);
    write_error_map_png(to_image(diff[k], cam.width, cam.height), run.dir / fmt::format("render_{}_error.png", stem), scale);
  }
  write_captioned(run.dir, "render", t,
              fmt::format("Fig.~7: mean $|I_\\mathrm{{discrete}} - I_\\mathrm{{analytic}}|$ over {}$\\times${} pixels",
                          cam.width, cam.height));
  // One scanline through the middle: intensity per pixel, the reference as its own series.
  Table line({"x", "method", "intensity"});
  const int y = cam.height / 2;
  for (int x = 0; x < cam.width; ++x) {
    const std::size_t i = static_cast<std::size_t>(y) * cam.width + x;
    line.add_row({static_cast<long>(x), std::string("analytic"), v.reference[i]});
    for (std::size_t k = 0; k < methods.size(); ++k)
      if (methods[k].correction != Correction::schulze) line.add_row({static_cast<long>(x), methods[k].label, v.methods[k][i]});
  }
  write_file_atomically(run.dir / "scanline.csv", line.to_csv());
  out.checks.push_back(at_most(CheckKind::derived, "render: values finite", static_cast<double>(nonfinite), 0, "non-finite pixels"));
  out.checks.push_back(at_most(CheckKind::derived, "render: reference error estimate", v.worst_estimate, s.scenes.reference_tol,
                               "worst per-pixel error estimate of the analytic integral, against the tolerance it was asked for"));
  for (bool centred : s.placements) {
    const double lac = mean[{centred, Correction::lacroute}], lee = mean[{centred, Correction::lee_newman}],
                 none = mean[{centred, Correction::none}];
    const std::string p = placement_name(centred);
    out.checks.push_back(at_most(CheckKind::regression, fmt::format("render ({}): lacroute and lee_newman comparable", p), std::fabs(lac - lee) / lac,
                                 s.b_comparable, "|lacroute - lee_newman| / lacroute, mean pixel difference (paper: 0.0895 vs 0.0894)"));
    if (centred)
      out.checks.push_back(holds(CheckKind::derived, "render (centred): none worse than both corrections", none > lac && none > lee,
                                 fmt::format("mean pixel difference none {:.4f} > lacroute {:.4f}, lee_newman {:.4f}", none, lac, lee)));
    else
      out.checks.push_back(holds(CheckKind::derived, "render (first): the half-step shift, corrected N = 5 worse than unit sampling",
                                 lac > unit_mean && lee > unit_mean,
                                 fmt::format("mean pixel difference lacroute {:.4f}, lee_newman {:.4f} > unit {:.4f} (none {:.4f})",
                                             lac, lee, unit_mean, none)));
  }
  out.parameters["render"] = {{"width", cam.width}, {"height", cam.height}, {"oversample", s.render_N},
                              {"unit_step", s.scenes.unit_step}, {"error_map_range", scale}};
  std::map<Correction, double> first;
  for (Correction c : s.corrections) first[c] = mean[{false, c}];
  return first;
}

// Error against the continuous integral as N grows, per placement.
void sweep_part(const OpacityStudy& s, const StudyRun& run, StudyOutcome& out) {
  const std::vector<Ray> rays = study_rays(s.scenes.analytic.box, run.quick ? s.quick_rays : s.rays, s.sweep_seed);
  Table t({"correction", "placement", "N", "mean_error", "max_error", "max_diff_from_none"});
  bool finite = true;
  double n1 = 0;
  const int first = s.sweep_N.front(), last = s.sweep_N.back();
  const int prev = s.sweep_N.size() > 1 ? s.sweep_N[s.sweep_N.size() - 2] : last;
  for (bool centred : s.placements) {
    const std::vector<SweepRow> rows = error_against_N(s.scenes, rays, s.corrections, s.sweep_N, centred, run.progress,
                                                        run.checkpoints, run.audit);
    std::map<Correction, std::map<int, double>> e;
    for (const SweepRow& r : rows) {
      t.add_row({name_of(r.correction), placement_name(centred), static_cast<long>(r.N), r.mean_error, r.max_error,
                 r.max_diff_from_none});
      finite = finite && r.finite;
      if (r.N == 1) n1 = std::max(n1, r.max_diff_from_none);
      e[r.correction][r.N] = r.mean_error;
    }
    const std::string p = placement_name(centred);
    const auto plateau = [&](Correction c) { return std::fabs(e[c][last] / e[c][prev] - 1); };
    out.checks.push_back(holds(CheckKind::derived, fmt::format("sweep ({}): none diverges as N grows", p),
                               e[Correction::none][last] > e[Correction::none][first],
                               fmt::format("none: mean error at N = {} above N = {}", last, first)));
    if (centred) {
      std::vector<double> h, err;
      for (int N : s.sweep_N) h.push_back(1.0 / N), err.push_back(e[Correction::lacroute][N]);
      out.checks.push_back(order_check("sweep (centred): lacroute converges, order 2 in 1/N", estimate_order(h, err), 2.0,
                                       s.order_tolerance));
      out.checks.push_back(at_most(CheckKind::derived, "sweep (centred): lee_newman stalls", plateau(Correction::lee_newman), s.b_plateau,
                                   fmt::format("|e(N = {}) / e(N = {}) - 1|: its target is the unit sample's transparency", last, prev)));
    } else {
      out.checks.push_back(at_most(CheckKind::derived, "sweep (first): lacroute stalls", plateau(Correction::lacroute), s.b_plateau,
                                   fmt::format("|e(N = {}) / e(N = {}) - 1|: the (N-1)H/(2N) shift of the oversamples", last, prev)));
    }
  }
  write_captioned(run.dir, "sweep", t, fmt::format("Mean $|I_N - I|$ over {} rays against the continuous integral", rays.size()));
  out.checks.push_back(holds(CheckKind::derived, "sweep: values finite", finite, "every correction, placement and N"));
  out.checks.push_back(at_most(CheckKind::identity, "sweep: N = 1 changes nothing", n1, 0, "max |value - value uncorrected| at N = 1"));
  out.parameters["sweep_rays"] = static_cast<long>(rays.size());
}

// Table 1: machine-dependent, only checked to be finite and positive.
std::map<Correction, double> timing_part(const OpacityStudy& s, const StudyRun& run, StudyOutcome& out) {
  const std::string load_before = read_loadavg();
  const int N = s.timing_N;
  const std::vector<double> groups =
      random_byte_groups(N, run.quick ? s.timing_quick_groups : s.timing_groups, s.fit_seed + 1);
  const int repeats = run.quick ? s.quick_repeats : s.repeats;
  Camera cam = s.camera;
  cam.width = run.quick ? s.timing_qw : s.timing_w;
  cam.height = run.quick ? s.timing_qh : s.timing_h;
  const int render_repeats = run.quick ? s.quick_render_repeats : s.render_repeats;
  // Round robin, best of the repeats: a load spike from the shared machine hits one pass of one
  // correction, not all passes of it.
  std::map<Correction, double> alone, whole;
  for (Correction c : s.corrections) alone[c] = whole[c] = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeats; ++r)
    for (Correction c : s.corrections) alone[c] = std::min(alone[c], correction_seconds_per_sample(c, groups, N, 1));
  render_seconds(s.scenes, cam, oversampled_config(Correction::none, N, s.scenes.unit_step, false), 1);  // warm-up
  for (int r = 0; r < render_repeats; ++r)
    for (Correction c : s.corrections)
      whole[c] = std::min(whole[c], render_seconds(s.scenes, cam, oversampled_config(c, N, s.scenes.unit_step, false), 1));
  const Correction q = Correction::lee_newman_quadratic;
  Table t({"part", "correction", "seconds", "lacroute_over_this", "paper_lacroute_over_quadratic"});
  t.allow_missing("lacroute_over_this");
  t.allow_missing("paper_lacroute_over_quadratic");
  t.set_format("seconds", "{:.4g}");
  t.set_format("lacroute_over_this", "{:.3f}");
  for (Correction c : s.corrections)
    t.add_row({std::string("correction alone, per sample"), name_of(c), alone[c],
               c == Correction::none ? kMissing : alone[Correction::lacroute] / alone[c],
               c == q ? s.paper_correction : kMissing});
  for (Correction c : s.corrections)
    t.add_row({fmt::format("whole render {}x{}", cam.width, cam.height), name_of(c), whole[c],
               whole[Correction::lacroute] / whole[c], c == q ? s.paper_overall : kMissing});
  write_captioned(run.dir, "timing", t, "Table~1 (machine-dependent): time and Lacroute's time over each correction's");
  const std::string load_after = read_loadavg();
  out.parameters["timing"] = {{"machine_dependent", true}, {"loadavg_before", load_before},
                              {"loadavg_after", load_after}, {"N", N}, {"groups", groups.size() / N},
                              {"repeats", repeats}, {"render_repeats", render_repeats}};
  if (has_q(s)) {
    const double rc = alone[Correction::lacroute] / alone[q], rw = whole[Correction::lacroute] / whole[q];
    out.checks.push_back(holds(CheckKind::identity, "timing: ratios finite and positive (machine-dependent)",
                               std::isfinite(rc) && rc > 0 && std::isfinite(rw) && rw > 0,
                               fmt::format("lacroute/quadratic: correction {:.2f} (paper {}), render {:.2f} (paper {})",
                                           rc, s.paper_correction, rw, s.paper_overall)));
    out.parameters["timing"]["ratio_correction"] = rc;
    out.parameters["timing"]["ratio_render"] = rw;
  }
  return whole;
}

// Speed against error: each correction's render time (timing) and its mean pixel difference
// (render), both with the paper's placement.
void speed_error_table(const OpacityStudy& s, const StudyRun& run, const std::map<Correction, double>& error,
                       const std::map<Correction, double>& seconds) {
  Table t({"correction", "render_seconds", "mean_abs_difference"});
  for (Correction c : s.corrections) t.add_row({name_of(c), seconds.at(c), error.at(c)});
  write_file_atomically(run.dir / "speed_error.csv", t.to_csv());
}

std::string heatmap(const std::string& quantity, Correction c) {
  const std::string n = name_of(c);
  return fmt::format(R"j({{"name": "surface_{0}_{1}", "csv": "surfaces.csv", "style": "heatmap", "x": "a", "y": "b",
     "z": "{0}", "where": {{"correction": "{1}"}}, "xlabel": "first sample (8-bit)", "ylabel": "second sample (8-bit)",
     "zlabel": "composited {0}", "title": "Fig. 3, N = 2: {0}, {1}"}})j",
                     quantity, n);
}

std::string plots_json() {
  std::vector<std::string> plots{
      R"j({"name": "sweep_first", "csv": "sweep.csv", "style": "lines", "x": "N", "y": "mean_error", "group": "correction",
     "where": {"placement": "first"}, "xscale": "log", "yscale": "log", "fit": true, "xlabel": "oversampling factor N",
     "ylabel": "mean |I_N - I| (continuous integral)", "title": "Error against N, oversamples from the unit sample on"})j",
      R"j({"name": "sweep_centred", "csv": "sweep.csv", "style": "lines", "x": "N", "y": "mean_error", "group": "correction",
     "where": {"placement": "centred"}, "xscale": "log", "yscale": "log", "fit": true, "xlabel": "oversampling factor N",
     "ylabel": "mean |I_N - I| (continuous integral)", "title": "Error against N, centred oversamples"})j",
      R"j({"name": "scanline", "csv": "scanline.csv", "style": "lines", "x": "x", "y": "intensity", "group": "method",
     "reference": {"column": "method", "value": "analytic"}, "xlabel": "pixel x (middle row)",
     "ylabel": "intensity", "title": "Fig. 7: one row of the 64^3 render"})j",
      R"j({"name": "speed_error", "csv": "speed_error.csv", "style": "points", "x": "render_seconds",
     "y": "mean_abs_difference", "group": "correction", "yscale": "log", "xlabel": "serial render time (s, machine-dependent)",
     "ylabel": "mean |I - I_analytic| (Fig. 7 render)", "title": "Speed against error, N = 5, oversamples from the unit sample on"})j",
      R"j({"name": "fit_error", "csv": "fit.csv", "style": "lines", "x": "N", "y": "mean", "where": {"set": "random 8-bit"},
     "xscale": "log", "yscale": "log", "hlines": [0.0031], "xlabel": "oversampling factor N",
     "ylabel": "mean |p_quadratic - p_exact|", "title": "Quadratic fit error, random 8-bit groups (dashed: paper, lobster)"})j"};
  for (const char* q : {"opacity", "intensity"})
    for (Correction c : {Correction::none, Correction::lacroute, Correction::lee_newman}) plots.push_back(heatmap(q, c));
  std::string out = "{\n  \"plots\": [\n    ";
  for (std::size_t i = 0; i < plots.size(); ++i) out += (i ? ",\n    " : "") + plots[i];
  return out + "\n  ]\n}\n";
}

}  // namespace

StudyWork opacity_work(const OpacityStudy& s, bool quick) {
  const auto samples = [&](Correction c, int N, bool centred, const Scene& scene) {
    return discrete_samples(oversampled_config(c, N, s.scenes.unit_step, centred), scene);
  };
  const Scene& grid = s.scenes.sampled;
  StudyWork work;
  const double pixels = quick ? double(s.quick_width) * s.quick_height : double(s.camera.width) * s.camera.height;
  // The reference, unit sampling, every (placement, correction) at render_N, and the fit's groups.
  double render = reference_evaluations(s.scenes.analytic, s.scenes.reference_tol) +
                  samples(Correction::none, 1, false, grid) + samples(Correction::none, s.render_N, false, grid);
  for (bool centred : s.placements)
    for (Correction c : s.corrections) render += samples(c, s.render_N, centred, grid);
  work.add("render (Fig. 7)", pixels, render);
  // Per placement: the reference, then at each N correction none and every correction.
  const Scene& analytic = s.scenes.analytic;
  double sweep = 0;
  for (bool centred : s.placements) {
    sweep += reference_evaluations(analytic, s.scenes.reference_tol);
    for (int N : s.sweep_N) {
      sweep += samples(Correction::none, N, centred, analytic);
      for (Correction c : s.corrections) sweep += samples(c, N, centred, analytic);
    }
  }
  work.add("sweep over N", static_cast<double>(quick ? s.quick_rays : s.rays), sweep);
  const double timed = quick ? double(s.timing_qw) * s.timing_qh : double(s.timing_w) * s.timing_h;
  const double passes = 1 + static_cast<double>(quick ? s.quick_render_repeats : s.render_repeats) *
                                static_cast<double>(s.corrections.size());
  work.add("timed renders (Table 1)", timed, passes * samples(Correction::none, s.timing_N, false, grid));
  return work;
}

StudyOutcome run_opacity_study(const OpacityStudy& s, const StudyRun& run) {
  StudyOutcome out;
  voxel_part(s, run, out);
  surfaces_part(s, run, out);
  fit_part(s, run, out);
  const std::map<Correction, double> error = render_part(s, run, out);
  sweep_part(s, run, out);
  speed_error_table(s, run, error, timing_part(s, run, out));
  write_file_atomically(run.dir / "plots.json", plots_json());
  out.parameters["quick"] = run.quick;
  long failed = 0;
  for (const StudyCheck& c : out.checks) failed += !c.pass;
  out.summary = fmt::format("{} checks, {} failed; timing ratios are machine-dependent", out.checks.size(), failed);
  return out;
}

}  // namespace vrv
