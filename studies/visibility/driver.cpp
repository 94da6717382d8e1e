// Study kind "visibility" (Gao, Huang, Shen, Kohl, IEEE Vis 2003): reads studies/visibility/visibility.toml,
// runs the four parts (opacity identities, the 58.4 samples, the early-termination sweep, block
// culling with POFs) and writes their tables, images and plots.json.  The parts live in
// parts.cpp; this file is the file format and the outputs.
#include <cmath>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "studies/engine/study_driver.h"
#include "studies/visibility/parts.h"

namespace vrv {
namespace {

PiecewiseLinear read_points(const StudyReader& r, const toml::table& t, std::string_view key,
                            std::string_view path) {
  const std::string p = StudyReader::child(path, key);
  const toml::array& a = r.array(r.require(t, key, path), p);
  std::vector<ControlPoint> points;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string pi = fmt::format("{}[{}]", p, i);
    const toml::array& xy = r.array(a[i], pi);
    if (xy.size() != 2) r.fail(pi, "expected [value, extinction]");
    const double v = r.number(xy[0], pi), y = r.number(xy[1], pi);
    if (y < 0) r.fail(pi, fmt::format("negative extinction {}", y));
    points.push_back({v, y});
  }
  try {
    return PiecewiseLinear(std::move(points));
  } catch (const std::invalid_argument& e) {
    r.fail(p, e.what());
  }
}

// A list of `count` whole numbers in [lo, hi].
std::vector<int> read_ints(const StudyReader& r, const toml::table& t, std::string_view key,
                           std::string_view path, std::size_t count, int lo, int hi) {
  const std::vector<long> x = r.whole_numbers(t, key, path, lo, hi);
  if (x.size() != count) r.fail(StudyReader::child(path, key), fmt::format("expected {} whole numbers", count));
  return std::vector<int>(x.begin(), x.end());
}

double open_unit(const StudyReader& r, const toml::table& t, std::string_view key, std::string_view path) {
  const double x = r.number(r.require(t, key, path), StudyReader::child(path, key));
  if (!(x > 0 && x < 1)) r.fail(StudyReader::child(path, key), fmt::format("must be in (0, 1), got {}", x));
  return x;
}

double positive(const StudyReader& r, const toml::table& t, std::string_view key, std::string_view path) {
  return r.positive(r.require(t, key, path), StudyReader::child(path, key));
}

VisibilityStudy read_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  const toml::table& doc = in.doc;
  r.check_keys(doc, "", {"kind", "name", "description", "scene", "identity", "threshold_samples",
                         "termination", "culling"});
  VisibilityStudy s;
  s.scene = read_study_scene(r, doc, "", s.scene_toml);
  if (!std::holds_alternative<GridField>(s.scene.field))
    r.fail("scene.field.kind", "block culling needs a grid field (kind = \"grid\")");
  if (s.scene.transfer.convention() != Convention::emission_extinction)
    r.fail("scene.transfer", "the identities scale the extinction: use emission/extinction");
  s.radiance = max_radiance(s.scene.transfer, s.scene.background);
  if (!std::isfinite(s.radiance))
    r.fail("scene.transfer", "colour g / tau is unbounded (g > 0 where tau = 0): no error bound");

  const toml::table& id = r.table(r.require(doc, "identity", ""), "identity");
  r.check_keys(id, "identity", {"ks", "basis2_extinction", "rays", "quick_rays", "seed", "step",
                                "reference_tol", "max_error", "max_transparency_error"});
  s.identity.ks = r.numbers(id, "ks", "identity", 1e-6, 1e6);
  s.identity.basis2 = read_points(r, id, "basis2_extinction", "identity");
  s.identity.rays = r.integer(r.require(id, "rays", "identity"), "identity.rays", 1, 100000);
  s.identity.quick_rays = r.integer(r.require(id, "quick_rays", "identity"), "identity.quick_rays", 1, 100000);
  s.identity.seed = static_cast<std::uint64_t>(
      r.integer(r.require(id, "seed", "identity"), "identity.seed", 0, 1L << 62));
  s.identity.step = positive(r, id, "step", "identity");
  s.identity.reference_tol = read_reference_tol(r, id, "identity");
  s.identity.max_error = positive(r, id, "max_error", "identity");
  s.identity.max_transparency_error = positive(r, id, "max_transparency_error", "identity");

  const toml::table& ts = r.table(r.require(doc, "threshold_samples", ""), "threshold_samples");
  r.check_keys(ts, "threshold_samples", {"alpha", "threshold", "paper_samples", "paper_rounding", "ray_samples"});
  s.samples.alpha = open_unit(r, ts, "alpha", "threshold_samples");
  s.samples.threshold = open_unit(r, ts, "threshold", "threshold_samples");
  s.samples.paper_samples = positive(r, ts, "paper_samples", "threshold_samples");
  s.samples.paper_rounding = positive(r, ts, "paper_rounding", "threshold_samples");
  s.samples.ray_samples =
      r.integer(r.require(ts, "ray_samples", "threshold_samples"), "threshold_samples.ray_samples", 1, 1000000);
  if (samples_to_threshold(s.samples.alpha, s.samples.threshold) >= s.samples.ray_samples)
    r.fail("threshold_samples.ray_samples", "the ray must be longer than the samples to the threshold");

  const toml::table& te = r.table(r.require(doc, "termination", ""), "termination");
  r.check_keys(te, "termination", {"thresholds", "image", "quick_image", "step", "reference_tol"});
  s.termination.thresholds = r.numbers(te, "thresholds", "termination", 1e-6, 1 - 1e-12);
  s.termination.image = r.integer(r.require(te, "image", "termination"), "termination.image", 1, 1024);
  s.termination.quick_image =
      r.integer(r.require(te, "quick_image", "termination"), "termination.quick_image", 1, 1024);
  s.termination.step = positive(r, te, "step", "termination");
  s.termination.reference_tol = read_reference_tol(r, te, "termination");

  const toml::table& cu = r.table(r.require(doc, "culling", ""), "culling");
  r.check_keys(cu, "culling", {"blocks", "views", "quick_views", "image", "quick_image", "threshold",
                               "step", "chord_fraction", "pof_block", "image_view"});
  const auto nb = read_ints(r, cu, "blocks", "culling", 3, 1, 64);
  s.culling.blocks = {nb[0], nb[1], nb[2]};
  const auto v = read_ints(r, cu, "views", "culling", 2, 1, 360);
  const auto qv = read_ints(r, cu, "quick_views", "culling", 2, 1, 360);
  s.culling.views = {v[0], v[1]};
  s.culling.quick_views = {qv[0], qv[1]};
  s.culling.image = r.integer(r.require(cu, "image", "culling"), "culling.image", 1, 1024);
  s.culling.quick_image = r.integer(r.require(cu, "quick_image", "culling"), "culling.quick_image", 1, 1024);
  s.culling.threshold = open_unit(r, cu, "threshold", "culling");
  s.culling.step = positive(r, cu, "step", "culling");
  s.culling.chord_fraction = positive(r, cu, "chord_fraction", "culling");
  const auto pb = read_ints(r, cu, "pof_block", "culling", 3, 0, 63);
  for (int a = 0; a < 3; ++a)
    if (pb[a] >= nb[a]) r.fail("culling.pof_block", fmt::format("block index {} outside the {} blocks", pb[a], nb[a]));
  s.culling.pof_block = pb[0] + nb[0] * (pb[1] + nb[1] * pb[2]);
  const auto iv = read_ints(r, cu, "image_view", "culling", 2, 0, 359);
  if (iv[0] >= v[0] || iv[1] >= v[1]) r.fail("culling.image_view", "outside the grid of views");
  s.culling.image_view = {iv[0], iv[1]};
  return s;
}

// The plots; the rotation plot keeps the row of views nearest the equator (as the paper's Fig. 4
// rotates about one axis).
std::string plots_json(const CullingResult& c) {
  return fmt::format(R"json({{
  "plots": [
    {{"name": "termination_error", "csv": "termination_plot.csv", "style": "lines",
     "x": "one_minus_threshold", "y": "value", "group": "series", "xscale": "log", "yscale": "log",
     "xlabel": "1 - termination threshold", "ylabel": "max |terminated - full| per pixel",
     "title": "Early termination: image error and its bound (1 - A) max radiance"}},
    {{"name": "termination_samples", "csv": "termination.csv", "style": "lines",
     "x": "one_minus_threshold", "y": "samples_saved", "xscale": "log",
     "xlabel": "1 - termination threshold", "ylabel": "share of samples saved",
     "title": "Early termination: samples saved"}},
    {{"name": "termination_speed_error", "csv": "termination.csv", "style": "points",
     "x": "samples", "y": "max_error_reference", "front": true,
     "xlabel": "samples per image", "ylabel": "max |discrete - reference| per pixel",
     "title": "Samples against error (reference integrator)"}},
    {{"name": "culling_share", "csv": "culling.csv", "style": "heatmap",
     "x": "theta", "y": "phi", "z": "share_culled_pof",
     "xlabel": "theta (degrees)", "ylabel": "phi (degrees)", "zlabel": "share of non-empty blocks culled",
     "title": "POF culling over the grid of views"}},
    {{"name": "culling_rotation", "csv": "culling_long.csv", "style": "lines",
     "x": "theta", "y": "share_culled", "group": "method", "where": {{"phi": "{}"}},
     "xlabel": "theta (degrees)", "ylabel": "share of non-empty blocks culled",
     "title": "Culling while rotating (phi = {} degrees)"}},
    {{"name": "culling_error", "csv": "culling_long.csv", "style": "lines",
     "x": "theta", "y": "max_error", "group": "method", "where": {{"phi": "{}"}},
     "hlines": [{}],
     "xlabel": "theta (degrees)", "ylabel": "max |culled - all| per pixel",
     "title": "Culling error and its bound (dashed)"}},
    {{"name": "pof_table", "csv": "pof.csv", "style": "heatmap",
     "x": "theta", "y": "phi", "z": "min_opacity",
     "xlabel": "theta (degrees)", "ylabel": "phi (degrees)", "zlabel": "POF (minimum opacity)",
     "title": "The plenoptic opacity function of block {}"}}
  ]
}}
)json",
                     c.equator_phi_text, c.equator_phi_text, c.equator_phi_text, c.bound, c.pof_block);
}

StudyPlan parse_visibility(const StudyInput& in) {
  const VisibilityStudy study = read_study(in);
  StudyJob job = [study](const StudyRun& run) {
    StudyOutcome out;
    const IdentityResult id = run_identity(study, run);
    const SamplesResult sm = run_threshold_samples(study, run);
    const TerminationResult te = run_termination(study, run);
    const CullingResult cu = run_culling(study, run);
    write_file_atomically(run.dir / "plots.json", plots_json(cu));
    for (const auto* part : {&id.checks, &sm.checks, &te.checks, &cu.checks})
      out.checks.insert(out.checks.end(), part->begin(), part->end());
    out.parameters = {{"scene", study.scene_toml},
                      {"max_radiance", study.radiance},
                      {"identity_rays", id.rays},
                      {"termination_image", te.side},
                      {"culling_views", {cu.n_theta, cu.n_phi}},
                      {"culling_image", cu.side}};
    out.summary = fmt::format(
        "identities within {:.1e}; {} samples to {}; culling {:.1f}% (POF) / {:.1f}% (chord) / {:.1f}% "
        "(sequential) of "
        "non-empty blocks over {} views, max error {:.2e} <= {:.2e}",
        id.max_difference, sm.discrete_samples, study.samples.threshold, 100 * cu.mean_share_pof,
        100 * cu.mean_share_chord, 100 * cu.mean_share_seq, cu.n_theta * cu.n_phi, cu.max_error, cu.bound);
    return out;
  };
  return {std::move(job), [study](bool quick) { return visibility_work(study, quick); }};
}

const RegisterStudyKind kVisibility{"visibility", parse_visibility};

}  // namespace
}  // namespace vrv
