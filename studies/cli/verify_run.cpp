#include "studies/cli/verify_run.h"

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>

#include <fmt/format.h>

#include "lib/bounds_file.h"
#include "lib/io/image_channels.h"
#include "lib/io/image_io.h"
#include "lib/io/output_paths.h"
#include "lib/io/stderr_capture.h"
#include "lib/work_estimate.h"
#include "lib/verify/verify_output.h"
#include "studies/engine/study_runner.h"

namespace vrv::cli {

namespace fs = std::filesystem;

namespace {

fs::path default_cache_dir() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "vrv";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "vrv";
  return {};
}

// An image is a regular file: a character device (/dev/zero) never ends and hung the reader, a
// FIFO can be read once.  VerifyInputError "<file>: is a ..., not an image file" otherwise.
void check_image_file(const std::string& file) {
  std::error_code ec;
  const fs::file_status s = fs::status(file, ec);
  if (!fs::exists(s) || fs::is_regular_file(s)) return;  // a missing file: the reader names it
  const char* kind = fs::is_directory(s)        ? "a directory"
                     : fs::is_character_file(s) ? "a character device"
                     : fs::is_block_file(s)     ? "a block device"
                     : fs::is_fifo(s)           ? "a FIFO"
                                                : "a special file";
  throw VerifyInputError(fmt::format("{}: is {}, not an image file", file, kind));
}

// The plot script's output is caught: a failure (a full disk: a 40-line Python traceback before)
// is said in one line, its last line quoted; what a drawn plot printed (warnings) is passed on.
std::string draw_plot(const fs::path& dir) {
  StderrCapture capture;
  const std::string why = draw_study_plots(dir);
  const std::string said = capture.release();
  if (why.empty()) {
    std::cerr << said;
    return {};
  }
  const std::string last = last_line(said);
  return last.empty() ? why : why + ": " + last;
}

}  // namespace

fs::path reference_cache_dir(const std::string& option, bool no_cache) {
  if (no_cache) return {};
  if (!option.empty()) {
    check_writable_dir(option, "--cache-dir");
    return option;
  }
  const fs::path dir = default_cache_dir();
  try {
    if (!dir.empty()) check_writable_dir(dir, "the default reference cache");
  } catch (const std::invalid_argument& e) {
    std::cerr << "vrv: " << e.what() << "; running without a cache\n";
    return {};
  }
  return dir;
}

std::vector<ImageWithStep> read_images(const std::vector<std::string>& files, const std::vector<double>& steps) {
  if (files.empty()) throw VerifyInputError("IMAGE: give the renderer's images, one per step");
  if (steps.size() != files.size())
    throw VerifyInputError(fmt::format("--steps: {} steps for {} images (one step per image, in the same order)",
                                       steps.size(), files.size()));
  std::vector<ImageWithStep> out;
  for (const std::string& file : files) check_image_file(file);
  for (std::size_t i = 0; i < files.size(); ++i) {
    try {
      out.push_back({files[i], steps[i], read_channel_image(files[i])});
    } catch (const std::runtime_error& e) {
      throw VerifyInputError(e.what());
    }
  }
  return out;
}

void check_image_steps(const Scene& scene, const std::vector<ImageWithStep>& images, const std::string& option) {
  constexpr double kMaxSamples = 1e12;  // a sample plan's own bound (lib/sampling.cpp)
  const double diagonal = (scene.box.max - scene.box.min).norm();
  for (const ImageWithStep& im : images)
    if (!(diagonal / im.step <= kMaxSamples))
      throw VerifyInputError(fmt::format(
          "{}: {}: step {:g} would take more than {:g} samples along the box's diagonal ({:.3g}), so vrv's models "
          "cannot be cast at it; give the step the image was rendered at (or --no-diagnosis)",
          im.name, option, im.step, kMaxSamples, diagonal));
}

std::optional<double> provenance_step(const std::string& file) {
  check_image_file(file);
  try {
    const std::optional<ImageProvenance> p = read_provenance(file);
    return p ? p->step : std::nullopt;
  } catch (const std::runtime_error& e) {
    throw VerifyInputError(e.what());
  }
}

std::vector<double> provenance_steps(const std::vector<std::string>& files) {
  std::vector<double> steps;
  for (const std::string& file : files) {
    const std::optional<double> step = provenance_step(file);
    if (!step)
      throw VerifyInputError(fmt::format("--steps: not given, and {} has no step in its provenance (vrv:step "
                                         "metadata): give --steps H1,H2,... one per image", file));
    steps.push_back(*step);
  }
  return steps;
}

VerifyRun run_verification(const Scene& scene, const std::vector<ImageWithStep>& images,
                           const VerifyOptions& options, const std::optional<BoundSet>& bounds,
                           const std::string& case_name, PublishedFolder* out,
                           const nlohmann::json& parameters, bool plots, const HtmlReportContext* html) {
  const auto start = std::chrono::steady_clock::now();
  VerifyRun run;
  run.report = verify_images(scene, images, options);
  if (bounds) run.rows = evaluate_bounds(case_name, run.report, *bounds);
  run.pass = run.report.pass && worst(run.rows) < BoundVerdict::fail;
  if (out) {
    std::vector<std::pair<std::string, Table>> extra;
    if (bounds) extra.emplace_back("bounds", bound_table(run.rows));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out->write_and_publish([&](const fs::path& dir) {
      write_verify_outputs(dir, run.report, extra, parameters, seconds);
      if (html) {
        HtmlReportContext context = *html;
        if (bounds) context.bounds = bound_table(run.rows);
        write_verify_report_html(dir / "report.html", run.report, context);
      }
      if (plots) run.plot_failure = draw_plot(dir);
    });
    if (!run.plot_failure.empty())
      std::cerr << fmt::format("vrv verify: {}: the plot could not be drawn: {}; or leave out --plots\n",
                               out->target().string(), run.plot_failure);
  }
  return run;
}

VerifyRun run_verification(const Scene& scene, const std::vector<ImageWithStep>& images,
                           const VerifyOptions& options, const std::optional<BoundSet>& bounds,
                           const std::string& case_name, const fs::path& out,
                           const nlohmann::json& parameters, bool plots, const HtmlReportContext* html) {
  std::optional<PublishedFolder> folder;
  if (!out.empty()) folder.emplace(out, kVerifyOutMarker, "--out");
  return run_verification(scene, images, options, bounds, case_name, folder ? &*folder : nullptr, parameters,
                          plots, html);
}

std::vector<std::string> invoking_commands() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string word, line;
  while (std::getline(in, word, '\0')) {
    if (!line.empty()) line += ' ';
    line += shell_quote(word);  // appended, not "x" + string: GCC 12's false -Wrestrict (bug 105651)
  }
  if (line.empty()) return {};
  std::error_code ec;
  return {"cd " + shell_quote(fs::current_path(ec).string()), line};
}

void add_plot_flags(CLI::App* cmd, bool& plots, const std::string& what) {
  // Drawing costs a Python process and matplotlib's import (~1 CPU s, more than the rest of a
  // cached verify): only where asked.  --no-plots, the default, stays accepted for scripts.
  // The plot is drawn into --out: without one --plots would be accepted and ignored.
  auto* on = cmd->add_flag("--plots", plots, what)->needs(cmd->get_option("--out"));
  cmd->add_flag("--no-plots")->description("Do not draw the plots (the default)")->excludes(on);
}

void run_exiting(const std::function<int()>& body) {
  if (const int rc = body(); rc != 0) throw CommandFailed(rc, "");  // main checks standard output first
}

std::string summary_text(const VerifyRun& run) {
  const VerifyReport& r = run.report;
  std::string s = fmt::format("{} ({}): {}", verdict_name(r.verdict.verdict), r.verdict_channel, r.verdict.reason);
  for (const OrderReport& o : r.orders)
    if (o.kind == OrderKind::self && o.channel == r.verdict_channel && std::isfinite(o.fit.order))
      s += fmt::format("; self-convergence order {:.3g}", o.fit.order);
  if (!r.diagnosis.empty())
    s += fmt::format("; behaves like {} to {:.2g} RMS", r.diagnosis.front().name, r.diagnosis.front().rms);
  for (const Fault& f : r.conventions)
    s += fmt::format("; behaves like: {} — consistent with the expected order {:g}", f.behaviour, *r.expected_order);
  for (const Fault& f : r.faults)
    s += f.kind == FaultKind::fitted ? fmt::format("; fault: {} (fitted: explains {:.0f} % of the error)", f.behaviour,
                                                   100 * r.fault_fits.front().confirmed)
                                     : fmt::format("; fault: {}", f.name());
  for (const std::string& n : r.notes) s += fmt::format("; {}", n);
  for (const std::string& f : r.failures) s += fmt::format("; FAIL: {}", f);
  for (const BoundRow& b : run.rows)
    if (b.verdict != BoundVerdict::pass)
      s += fmt::format("; {} {} {} = {:.4g} (limit {:.4g})", bound_verdict_name(b.verdict), b.bound, b.where,
                       b.measured, b.limit);
  return s;
}

}  // namespace vrv::cli
