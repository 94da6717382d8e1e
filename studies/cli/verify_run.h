#pragma once
// What `vrv verify` and `vrv gate` share: the reference cache directory, one verification with
// its bounds, its files and its exit code.
//
// Exit codes (studies/cli/cli_support.h, docs/verify.md), after OpenImageIO's idiff where they fit:
//   0  pass: every bound within its fail limit (warnings are reported, as idiff's warnings are,
//      but do not fail: a gate fails on its fail levels)
//   1  failure: a fail or hard-fail bound crossed, the expected order missed, the reference
//      missed its tolerance, or a gated study's check failed (idiff: 2)
//   2  bad input: options, bounds or scene file, an unreadable image, images of different sizes,
//      NaN pixels (idiff: 3 for different sizes, 4 for unreadable files)
// vrv keeps its own convention (1 = a check failed, 2 = bad input, the same for every subcommand)
// so that CI scripts read every vrv command alike; idiff's separate warning code is not used
// because a warning that fails CI is a fail level.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "lib/gate.h"
#include "lib/verify.h"
#include "lib/verify/verify_report_html.h"
#include "lib/verify_work.h"  // check_verification_work, kDefaultVerifyWorkLimit
#include "studies/cli/cli_support.h"
#include "studies/cli/published_folder.h"

namespace vrv::cli {


// The reference cache to use, checked before any work: `option` (--cache-dir; std::invalid_argument
// when it cannot be written), else $XDG_CACHE_HOME/vrv, else $HOME/.cache/vrv when it can be
// written (else none, said in one stderr line: an optional cache never fails a run); none with
// `no_cache`.
std::filesystem::path reference_cache_dir(const std::string& option, bool no_cache);

struct VerifyRun {
  VerifyReport report;
  std::vector<BoundRow> rows;
  bool pass = true;  // report.pass and no row beyond fail
  std::string plot_failure;  // why the plot was not drawn (said on stderr; vrv verify exits 1)
};

// Verifies, evaluates `bounds` (if any) for `case_name`, and writes the outputs into `out`
// (if not null) with the plot if `plots`, and with `html` the page report.html
// (verify_report_html.h, the bounds' rows added), then publishes it whole (published_folder.h).
// Throws VerifyInputError / std::invalid_argument for bad input.
VerifyRun run_verification(const Scene& scene, const std::vector<ImageWithStep>& images,
                           const VerifyOptions& options, const std::optional<BoundSet>& bounds,
                           const std::string& case_name, PublishedFolder* out,
                           const nlohmann::json& parameters, bool plots, const HtmlReportContext* html = nullptr);
// The same into the folder `out` (if not empty), its PublishedFolder made here (vrv gate's cases).
VerifyRun run_verification(const Scene& scene, const std::vector<ImageWithStep>& images,
                           const VerifyOptions& options, const std::optional<BoundSet>& bounds,
                           const std::string& case_name, const std::filesystem::path& out,
                           const nlohmann::json& parameters, bool plots, const HtmlReportContext* html = nullptr);

// The command line this process was started with (/proc/self/cmdline), each word shell-quoted,
// after a `cd` to the working folder: what the HTML report shows under "To reproduce".  Empty
// where /proc is not there.
std::vector<std::string> invoking_commands();

// What marks a folder as a verification's outputs (check_replaceable_dir, lib/io/output_paths.h).
inline constexpr const char* kVerifyOutMarker = "meta.json";

// A subcommand's callback around `body` (verify, gate): a non-zero result is the exit code.  Errors
// (a bad bounds file: BoundsFileError, "<file>: <key>: <reason>") are main's, "vrv: error: ...",
// exit 2, as for every command.
// --plots (draw the log-log plot into --out; refused without --out, which must be declared
// first) and --no-plots (the default), for verify and gate.
void add_plot_flags(CLI::App* cmd, bool& plots, const std::string& what);

void run_exiting(const std::function<int()>& body);

// The summary line on stderr: verdict, orders, nearest model, faults, failed bounds.
std::string summary_text(const VerifyRun& run);

// The sample distance the file's provenance records (vrv:step), if any; VerifyInputError when the
// file cannot be read.
std::optional<double> provenance_step(const std::string& file);

// The sample distance each file's provenance records (ImageProvenance::step, lib/io/image_io.h),
// for images written by vrv render or a renderer that writes "vrv:step"; VerifyInputError naming
// the first file without one.
std::vector<double> provenance_steps(const std::vector<std::string>& files);

// The diagnosis casts vrv's models at each image's step: a step giving more than 1e12 samples on
// the box's diagonal (--steps ...,1e-320) is refused naming the image and where its step came from
// (`option`: "--steps" or "vrv:step"), before the reference; VerifyInputError.
void check_image_steps(const Scene& scene, const std::vector<ImageWithStep>& images, const std::string& option);

// Reads IMAGE files and pairs them with steps (same count); VerifyInputError naming the file.
std::vector<ImageWithStep> read_images(const std::vector<std::string>& files, const std::vector<double>& steps);

}  // namespace vrv::cli
