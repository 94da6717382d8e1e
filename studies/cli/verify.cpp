// vrv verify: a renderer's images at several sample distances against the reference: errors,
// orders, a verdict, a diagnosis and, with --bounds, a gate.  See docs/verify.md.
#include <charconv>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "lib/bounds_file.h"
#include "lib/io/output_paths.h"
#include "lib/util/parallel.h"
#include "lib/util/ranks.h"
#include "lib/scene_file.h"
#include "lib/scene_mode.h"
#include "lib/verify/verify_output.h"
#include "studies/cli/memory_limit.h"
#include "studies/cli/verify_run.h"
#include "studies/engine/interrupt.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/discrete_flags.h"
#include "studies/cli/commands.h"

namespace vrv::cli {
namespace {

namespace fs = std::filesystem;

struct VerifyCliOptions {
  std::string scene;
  std::optional<double> max_memory_gib;  // --max-memory: the scene's volume
  std::vector<std::string> images;
  std::optional<std::string> steps;  // none: from the images' provenance
  std::optional<double> expected_order;
  std::string bounds, case_name;
  std::string out;
  std::string report;  // --report FILE.html
  VerifySettings settings;  // --tol, --order-tolerance, --order-metric, --unit-distance, --alpha
  std::optional<double> threshold;
  std::string mode;  // --mode: projection images (default: the scene's mode)
  std::string cache_dir;
  bool no_cache = false, no_diagnosis = false, plots = false, quiet = false;
  double max_work = kDefaultVerifyWorkLimit;
  int threads = 0;
};

std::vector<double> parse_steps(const std::string& text) {
  std::vector<double> steps;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    double v = 0;
    const auto [p, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (ec != std::errc() || p != item.data() + item.size() || !(v > 0) || !std::isfinite(v))
      throw std::invalid_argument(fmt::format("--steps: '{}' is not a positive number", item));
    steps.push_back(v);
  }
  return steps;
}

int run_verify(const VerifyCliOptions& o) {
  check_threads(o.threads);
  const InterruptGuard interrupts;  // before any thread: SIGINT leaves --out as it was (published_folder.h)
  const Scene scene = load_scene_or_default(o.scene, memory_limit_bytes(o.max_memory_gib));
  VerifyOptions opt;
  opt.scene_text = scene_text_or_default(o.scene);
  apply(o.settings, opt);
  opt.expected_order = o.expected_order;
  if (const std::string mode = chosen_mode(o.mode, opt.scene_text); !mode.empty()) {
    opt.mode = parse_projection_mode(mode);
    if (!opt.mode)
      throw std::invalid_argument(fmt::format("--mode: unknown value '{}' (one of {}, {})", mode,
                                              projection_mode_list(), kEmissionAbsorption));
    // Named here, where the file's name is known (the library's own checks say "scene").
    const std::string name = o.scene.empty() ? "the default scene" : o.scene;
    require_unshaded(scene, name, "vrv verify with a projection mode");
    require_grey(scene, name, "vrv verify with a projection mode");
  }
  opt.diagnose = !o.no_diagnosis;
  opt.progress = !o.quiet;
  std::optional<BoundSet> bounds;
  if (!o.bounds.empty()) {
    const BoundsFile file = load_bounds(o.bounds);
    bounds = chosen_bounds(file, o.case_name.empty() ? std::nullopt : std::optional(o.case_name));
    use_bounds(*bounds, opt, o.threshold);
  } else if (!o.case_name.empty()) {
    throw std::invalid_argument("--case: needs --bounds");
  }
  if (o.threshold) opt.threshold = *o.threshold;
  std::vector<fs::path> inputs(o.images.begin(), o.images.end());
  inputs.insert(inputs.end(), {fs::path(o.scene), fs::path(o.bounds)});
  // Under MPI (docs/distributed.md) every rank verifies; rank 0 alone checks and writes outputs.
  if (!o.out.empty() && is_output_rank()) check_verify_out(o.out, inputs);
  if (!o.report.empty() && is_output_rank()) check_verify_report_path(o.report, inputs, o.out, "--report");
  const std::vector<ImageWithStep> images =
      read_images(o.images, o.steps ? parse_steps(*o.steps) : provenance_steps(o.images));
  std::vector<double> steps;
  for (const ImageWithStep& im : images) steps.push_back(im.step);
  if (opt.diagnose) check_image_steps(scene, images, o.steps ? "--steps" : "vrv:step");
  check_verification_work(scene, opt, images.front().image.width, images.front().image.height, steps, 0,
                          o.max_work, "--max-work");
  // Where results go is checked (and locked) before the reference is computed, not after.
  std::optional<PublishedFolder> out;
  if (!o.out.empty() && is_output_rank()) out.emplace(o.out, kVerifyOutMarker, "--out");
  opt.cache_dir = reference_cache_dir(o.cache_dir, o.no_cache);
  const ThreadLimit threads(o.threads);
  const nlohmann::json parameters = {{"command", "verify"}, {"scene", o.scene}, {"images", o.images},
                                     {"steps", o.steps.value_or("")}, {"expected_order", o.expected_order ? nlohmann::json(*o.expected_order) : nlohmann::json(nullptr)},
                                     {"bounds", o.bounds}, {"case", o.case_name}, {"alpha", o.settings.alpha},
                                     {"threshold", opt.threshold}, {"tol", o.settings.tol}, {"order_metric", o.settings.order_metric},
                                     {"mode", opt.mode ? std::string(projection_mode_name(*opt.mode)) : std::string()}};
  const PixelSharing sharing;
  const VerifyRun run = run_verification(scene, images, opt, bounds, o.case_name.empty() ? "verify" : o.case_name,
                                         out ? &*out : nullptr, parameters, o.plots);
  if (!o.report.empty() && is_output_rank()) {
    HtmlReportContext context{"vrv verify", invoking_commands(), {}};
    if (bounds) context.bounds = bound_table(run.rows);
    try {
      write_verify_report_html(o.report, run.report, context);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("--report: {}: not written: {}", o.report, e.what()));
    }
  }
  if (!o.quiet) std::cerr << "vrv verify: " << summary_text(run) << '\n';
  nlohmann::ordered_json j = to_json(run.report);
  j["pass"] = run.pass;
  if (bounds) j["bounds"] = nlohmann::ordered_json::parse(bound_table(run.rows).to_json());
  if (!o.out.empty()) j["out"] = o.out;
  if (!o.report.empty()) j["report"] = o.report;
  // A plot that could not be drawn fails the run, as it fails a study: the tables are published.
  if (!run.plot_failure.empty()) j["plots"] = "failed: " + run.plot_failure;
  const int rc = run.pass && run.plot_failure.empty() ? kExitPass : kExitCheckFailed;
  j["exit"] = rc;
  std::cout << j.dump() << '\n';
  return rc;
}

}  // namespace

void add_verify_command(CLI::App& app) {
  auto o = std::make_shared<VerifyCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "verify", "Verify a renderer from its images at several sample distances: errors against the "
                "reference, observed and self-convergence orders, a verdict, a diagnosis, bounds");
  cmd->footer(
      "Images: anything OpenImageIO reads (EXR, TIFF, PFM, PNG), grey or RGB(A), all of one size, "
      "rendered with the scene's camera (or the default camera) at the sizes they have.\n"
      "Exit: 0 pass, 1 failure (expected order missed, reference tolerance missed, a bound's fail "
      "level crossed, the plot not drawn), 2 bad input or --out not written. stdout: one JSON line. See docs/verify.md.\n"
      "MPI: in a build with -DVRV_WITH_MPI=ON, `mpirun -np P vrv verify ...` spreads the reference image's pixels "
      "over P ranks; every output is bitwise that of one process (docs/distributed.md).");
  cmd->add_option("--scene", o->scene, "Scene file (TOML); the embedded default when omitted");
  add_volume_memory_option(*cmd, o->max_memory_gib);
  cmd->add_option("images", o->images, "The renderer's images, one per step")->required();
  cmd->add_option("--steps", o->steps, "Sample distances (world units), one per image: H1,H2,...; "
                                       "default: each image's provenance (vrv:step metadata)");
  cmd->add_option("--expected-order", o->expected_order, "Fail unless the error converges at this order "
                                                          "(with --mode: 2 unless given)");
  cmd->add_option("--mode", o->mode, "Projection images: xray | xray_classified | mip | mip_classified (default: the "
                                     "scene's `mode`; emission_absorption overrides it); see docs/projections.md");
  cmd->add_option("--order-tolerance", o->settings.order_tolerance, "Observed >= K - this converges at K")->capture_default_str();
  cmd->add_option("--order-metric", o->settings.order_metric, "Statistic the orders fit: rms, max, mean, p99")->capture_default_str();
  cmd->add_option("--bounds", o->bounds, "Bounds file (TOML): gate on its [defaults] (or --case)");
  cmd->add_option("--case", o->case_name, "With --bounds: the case whose bounds apply");
  cmd->add_option("--out", o->out, "Write tables, error images, plots.json and meta.json (and with --plots the plot) into this directory");
  cmd->add_option("--report", o->report, "Write the verification as one self-contained HTML page (verdict, fault, "
                                         "plot, error maps, regions, catalogue, commands) to this file");
  cmd->add_option("--alpha", o->settings.alpha, "Colour channels with an alpha channel: auto (straight where the file declares it, as PNG does; else "
                  "premultiplied), premultiplied or straight")->capture_default_str();
  cmd->add_option("--threshold", o->threshold,
                  fmt::format("Count pixels with |error| above this (default {:g})", VerifyOptions{}.threshold));
  add_shared_option(*cmd, Option::tol, o->settings.tol);
  cmd->add_option("--cache-dir", o->cache_dir, "Reference cache (default $XDG_CACHE_HOME/vrv or ~/.cache/vrv)");
  cmd->add_flag("--no-cache", o->no_cache, "Do not read or write the reference cache");
  cmd->add_flag("--no-diagnosis", o->no_diagnosis, "Skip casting vrv's own models");
  cmd->add_option("--unit-distance", o->settings.unit_distance, "Unit distance of the uncorrected-opacity models (default: the largest step)");
  add_plot_flags(cmd, o->plots, "With --out: draw the log-log plot error_vs_step.{png,pdf} (~1 CPU s)");
  cmd->add_option("--threads", o->threads, "Threads (default: all cores)");
  cmd->add_option("--max-work", o->max_work,
                  "Field evaluations the reference may take, estimated before it is computed")
      ->capture_default_str();
  cmd->add_flag("--quiet", o->quiet, "No progress or summary on stderr");
  cmd->callback([o] { run_exiting([&] { return run_verify(*o); }); });
}

}  // namespace vrv::cli
