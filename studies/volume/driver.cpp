// Study kind "volume" (issue 27): vrv's discrete methods on a real scan (a `kind = "volume"`
// scene) against the exact reference: per method and step the image's mean and largest error,
// the observed order against the expected one, the reference image and each method's error map.
// The rendering is the segment-rules study's (studies/segment-rules/images.cpp, run_render), so
// both studies measure images the same way; this file reads the study and writes its outputs.
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/io/atomic_file.h"
#include "lib/io/table.h"
#include "studies/engine/study_driver.h"
#include "studies/engine/study_outputs.h"
#include "studies/segment-rules/segment_rules.h"

namespace vrv {
namespace {

struct VolumeStudy {
  std::vector<RuleSpec> rules;
  Strategy strategy = Strategy::inviwo;
  double reference_tol = 1e-11;
  OrderTolerance order_tolerance;
  RenderSpec render;
};

VolumeStudy read_volume_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  r.check_keys(in.doc, "", {"kind", "name", "description", "images", "render"});
  VolumeStudy st;
  ImageSettings images = read_images(r, in.doc);
  st.strategy = images.strategy;
  st.reference_tol = images.reference_tol;
  st.order_tolerance = images.order_tolerance;
  st.rules = std::move(images.rules);
  st.render = read_render(r, r.table(r.require(in.doc, "render", ""), "render"), "render");
  if (!std::holds_alternative<GridField>(st.render.scene.field) || st.render.scene.field_files.empty())
    r.fail("render.scene.field", "the volume study needs a volume file (kind = \"volume\")");
  return st;
}

std::string plots_json(const VolumeStudy& st) {
  const nlohmann::json plot = {
      {"name", "convergence_" + st.render.name}, {"csv", "image_errors.csv"}, {"style", "lines"},
      {"x", "step"}, {"y", "mean_error"}, {"group", "rule"}, {"xscale", "log"}, {"yscale", "log"},
      {"fit", true}, {"xlabel", "step (mm)"}, {"ylabel", "mean |discrete - reference| over pixels"},
      {"title", fmt::format("Image error against step: {}", st.render.name)}};
  return nlohmann::json{{"plots", nlohmann::json::array({plot})}}.dump(2) + "\n";
}

StudyOutcome run_volume_study(const VolumeStudy& st, const StudyRun& run) {
  const RenderSpec& spec = st.render;
  const RenderResult res = run_render(spec, st.rules, st.strategy, st.reference_tol, run.audit, run.quick, run.progress,
                                      run.checkpoints, "render");
  StudyOutcome out;
  Table errors({"rule", "step", "mean_error", "max_error", "samples_per_ray"});
  for (const char* c : {"mean_error", "max_error"}) errors.set_format(c, "{:.4e}");
  long bad_rows = 0;
  for (const ImageErrorRow& row : res.rows) {
    bad_rows += !(std::isfinite(row.mean_error) && std::isfinite(row.max_error));
    errors.add_row({std::string(segment_rule_name(row.rule)), row.step, row.mean_error, row.max_error,
                    row.samples_per_ray});
  }
  out.checks.push_back({"finite image errors", static_cast<double>(bad_rows), 0, bad_rows == 0,
                        "(rule, step) rows whose mean or largest image error is not finite", CheckKind::finite});
  out.checks.push_back({"pixels on the scan", static_cast<double>(res.hit_pixels), 1, res.hit_pixels >= 1,
                        "pixels whose ray meets the scan's box (the means are over them)", CheckKind::finite});

  Table orders({"rule", "expected_order", "observed_order", "standard_error", "pass"});
  orders.set_format("observed_order", "{:.3f}");
  orders.set_format("standard_error", "{:.2g}");
  Table maps({"rule", "step", "max_abs_error", "file"});
  std::filesystem::create_directories(run.dir / "images");
  write_value_image(res.reference, run.dir / "images" / (spec.name + "_reference"));
  for (std::size_t r = 0; r < st.rules.size(); ++r) {
    const std::string rule(segment_rule_name(st.rules[r].rule));
    const OrderEstimate& fit = res.fits[r];
    const double expected = st.rules[r].expected_order;
    const bool pass = order_matches(fit, expected, st.order_tolerance);
    orders.add_row({rule, expected, std::isfinite(fit.order) ? fit.order : -1.0, fit.standard_error,
                    std::string(!spec.check_orders ? "not gated" : pass ? "yes" : "no")});
    if (spec.check_orders) out.checks.push_back(order_check("order " + rule, fit, expected, st.order_tolerance));
    const std::string file = fmt::format("images/{}_{}_error", spec.name, rule);
    write_error_image(res.error_maps[r], run.dir / file);
    maps.add_row({rule, spec.map_step, max_abs_pixel(res.error_maps[r]), file + ".png"});
  }
  write_table(run.dir, "image_errors", errors,
              {fmt::format("Image error per rule and step on {} ({}x{} pixels)", spec.name, res.width, res.height),
               "tab:volume-errors", {}});
  write_table(run.dir, "orders", orders, {"Observed order of the image error per rule", "tab:volume-orders", {}});
  write_table(run.dir, "error_maps", maps, {});
  write_file_atomically(run.dir / "plots.json", plots_json(st));

  out.parameters = {{"strategy", strategy_name(st.strategy)}, {"reference_tol", st.reference_tol},
                    {"width", res.width}, {"height", res.height}, {"hit_pixels", res.hit_pixels},
                    {"steps", run.quick ? spec.quick_steps : spec.steps}, {"map_step", spec.map_step},
                    {"scene", spec.scene_toml}};
  long failed = 0;
  for (const StudyCheck& c : out.checks) failed += !c.pass;
  out.summary = fmt::format("{}: {} rules at {} steps; {} of {} checks failed", spec.name, st.rules.size(),
                            (run.quick ? spec.quick_steps : spec.steps).size(), failed, out.checks.size());
  return out;
}

StudyPlan parse_volume_study(const StudyInput& in) {
  VolumeStudy st = read_volume_study(in);
  return {[st](const StudyRun& run) { return run_volume_study(st, run); },
          [st](bool quick) {
            StudyWork work;
            add_render_work(st.render, st.rules, st.strategy, st.reference_tol, quick, work);
            return work;
          }};
}

const RegisterStudyKind kVolume{"volume", parse_volume_study};

}  // namespace
}  // namespace vrv
