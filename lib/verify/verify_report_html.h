#pragma once
// `vrv verify --report FILE.html` (and `vrv gate --report`, `vrv.verify(report=...)`): the
// verification as one self-contained HTML page, for people to look at.  In this order: the
// verdict and the named fault (or the convention, or "no fault named"), the convergence plot (an
// inline SVG drawn from the fitted points, so no Python is needed), the error maps of every image
// and channel (inline base64 PNGs made by the image module, each with a numbered colour bar), the
// region table, the fitted fault catalogue's ranking with its parameters and vrv's nearest
// models, and the commands that reproduce the page.  Inline CSS, no script, no external request:
// the file can be mailed or archived and opened anywhere.  Every user-provided string (image and
// scene file names, channel names, commands) is HTML-escaped.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lib/io/table.h"
#include "lib/verify/verify_report.h"

namespace vrv {

struct HtmlReportContext {
  std::string title = "vrv verify";   // the page's heading prefix (vrv gate: "vrv gate: case NAME")
  std::vector<std::string> commands;  // shell commands that reproduce the report, shown verbatim
  std::optional<Table> bounds;        // the bounds' rows when the verification was gated
};

// `text` with &, <, >, " and ' replaced by entities: safe in element text and quoted attributes.
std::string html_escape(std::string_view text);

// `word` as one POSIX shell word: unchanged when it holds only safe characters, else in single
// quotes (a ' inside written '\'').
std::string shell_quote(std::string_view word);

// RFC 4648 base64 of `bytes` (with '=' padding).
std::string base64(std::string_view bytes);

// The page.  Loads the image module (lib/io/image_module.h) for the PNGs; std::runtime_error,
// one line, when an image cannot be encoded.
std::string verify_report_html(const VerifyReport& report, const HtmlReportContext& context);

// Before any work: `path` names a file (not a directory), is none of `inputs` (images, scene,
// bounds file) under any name, does not lie inside `out_dir` (a folder replaced whole, which would
// remove it), and its folder can be written (created if missing, as --out's is); the image module
// loads.  std::invalid_argument "<option>: <path>: <reason>" otherwise.
void check_verify_report_path(const std::filesystem::path& path, const std::vector<std::filesystem::path>& inputs,
                              const std::filesystem::path& out_dir, std::string_view option);

// The page built whole in memory, then written atomically (lib/io/atomic_file.h): the file is the
// previous one or the new one, never a part.
void write_verify_report_html(const std::filesystem::path& path, const VerifyReport& report,
                              const HtmlReportContext& context);

}  // namespace vrv
