#include "lib/verify/verify_report_html.h"


#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <boost/archive/iterators/base64_from_binary.hpp>
#include <boost/archive/iterators/transform_width.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/io/atomic_file.h"
#include "lib/io/image_io.h"
#include "lib/io/image_module.h"
#include "lib/io/numbered_error_map.h"
#include "lib/io/output_paths.h"
#include "lib/io/scratch_folder.h"
#include "lib/verify/verify_output.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

constexpr int kShownSide = 256;  // small images are scaled up (pixelated) to about this height
constexpr std::size_t kShownModels = 10;

std::string g3(double v) { return std::isfinite(v) ? fmt::format("{:.3g}", v) : std::string("n/a"); }
std::string percent(double v) { return std::isfinite(v) ? fmt::format("{:.1f} %", 100 * v) : std::string("n/a"); }

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  if (!in && !in.eof()) throw std::runtime_error(fmt::format("{}: cannot read back the report's image", path.string()));
  return s.str();
}

std::string data_uri(const fs::path& png) { return "data:image/png;base64," + base64(file_bytes(png)); }

// A table's rows as HTML: numbers to 3 significant digits, right-aligned; every cell escaped.
std::string html_table(const Table& table, const std::string& id) {
  const nlohmann::json rows = nlohmann::json::parse(table.to_json());
  std::string s = fmt::format("<div class=\"scroll\"><table id=\"{}\"><thead><tr>", html_escape(id));
  for (const std::string& c : table.columns()) s += "<th>" + html_escape(c) + "</th>";
  s += "</tr></thead><tbody>\n";
  for (const nlohmann::json& row : rows) {
    s += "<tr>";
    for (const std::string& c : table.columns()) {
      const nlohmann::json& v = row.at(c);
      if (v.is_string()) s += "<td>" + html_escape(v.get<std::string>()) + "</td>";
      else if (v.is_number_integer()) s += fmt::format("<td class=\"num\">{}</td>", v.get<long>());
      else if (v.is_number()) s += "<td class=\"num\">" + g3(v.get<double>()) + "</td>";
      else s += "<td class=\"num\">n/a</td>";
    }
    s += "</tr>\n";
  }
  return s + "</tbody></table></div>\n";
}

// The log-log plot of every order's points, drawn here from the numbers (no Python, no
// matplotlib): decade ticks, one colour per series, the fitted slope dashed.
std::string convergence_svg(const std::vector<OrderReport>& orders) {
  static constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                             "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22"};
  struct Series {
    std::string label;
    std::vector<std::pair<double, double>> points;  // log10 h, log10 e
    double order;
  };
  std::vector<Series> series;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const OrderReport& o : orders) {
    Series s{fmt::format("{} {}", o.channel, o.kind == OrderKind::self ? "successive differences" : "against the reference"),
             {}, o.fit.order};
    for (std::size_t k = 0; k < o.steps.size() && k < o.errors.size(); ++k)
      if (o.steps[k] > 0 && o.errors[k] > 0 && std::isfinite(o.errors[k])) {
        s.points.emplace_back(std::log10(o.steps[k]), std::log10(o.errors[k]));
        x0 = std::min(x0, s.points.back().first), x1 = std::max(x1, s.points.back().first);
        y0 = std::min(y0, s.points.back().second), y1 = std::max(y1, s.points.back().second);
      }
    if (!s.points.empty()) series.push_back(std::move(s));
  }
  if (series.empty()) return "<p>No positive errors to plot.</p>\n";
  x0 = std::floor(x0), x1 = std::ceil(x1), y0 = std::floor(y0), y1 = std::ceil(y1);
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + 1;
  const double W = 560, ml = 70, mr = 20, mt = 20, plot_h = 300, mb = 50;
  const double legend_h = 18.0 * static_cast<double>(series.size()) + 10;
  const double H = mt + plot_h + mb + legend_h;
  const auto X = [&](double l) { return ml + (l - x0) / (x1 - x0) * (W - ml - mr); };
  const auto Y = [&](double l) { return mt + plot_h - (l - y0) / (y1 - y0) * plot_h; };
  std::string s = fmt::format(
      "<svg id=\"convergence-plot\" xmlns=\"http://www.w3.org/2000/svg\" role=\"img\" width=\"{0}\" height=\"{1}\" "
      "viewBox=\"0 0 {0} {1}\" font-family=\"sans-serif\" font-size=\"12\">\n"
      "<title>error against sample distance, log-log</title>\n"
      "<rect x=\"{2}\" y=\"{3}\" width=\"{4}\" height=\"{5}\" fill=\"none\" stroke=\"#444\"/>\n",
      W, H, ml, mt, W - ml - mr, plot_h);
  const int ystep = y1 - y0 > 8 ? 2 : 1;
  for (double e = x0; e <= x1 + 0.5; e += 1)
    s += fmt::format("<line x1=\"{0:.1f}\" x2=\"{0:.1f}\" y1=\"{1}\" y2=\"{2}\" stroke=\"#ddd\"/>"
                     "<text x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">1e{4:g}</text>\n",
                     X(e), mt, mt + plot_h, mt + plot_h + 16, e);
  for (double e = y0; e <= y1 + 0.5; e += ystep)
    s += fmt::format("<line x1=\"{0}\" x2=\"{1}\" y1=\"{2:.1f}\" y2=\"{2:.1f}\" stroke=\"#ddd\"/>"
                     "<text x=\"{3}\" y=\"{4:.1f}\" text-anchor=\"end\">1e{5:g}</text>\n",
                     ml, W - mr, Y(e), ml - 6, Y(e) + 4, e);
  s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">sample distance h</text>\n", (ml + W - mr) / 2,
                   mt + plot_h + 34);
  s += fmt::format("<text transform=\"translate(16 {}) rotate(-90)\" text-anchor=\"middle\">error</text>\n",
                   mt + plot_h / 2);
  for (std::size_t i = 0; i < series.size(); ++i) {
    const Series& r = series[i];
    const char* colour = kColours[i % std::size(kColours)];
    std::string line;
    for (const auto& [lx, ly] : r.points) line += fmt::format("{:.1f},{:.1f} ", X(lx), Y(ly));
    s += fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"/>\n", line, colour);
    for (const auto& [lx, ly] : r.points)
      s += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"{}\"/>\n", X(lx), Y(ly), colour);
    if (std::isfinite(r.order) && r.points.size() >= 2) {  // the fit: slope p through the points' centroid
      double a = 0;
      for (const auto& [lx, ly] : r.points) a += ly - r.order * lx;
      a /= static_cast<double>(r.points.size());
      const auto [lo, hi] = std::minmax_element(r.points.begin(), r.points.end());
      s += fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"{}\" "
                       "stroke-dasharray=\"5 4\"/>\n",
                       X(lo->first), Y(a + r.order * lo->first), X(hi->first), Y(a + r.order * hi->first), colour);
    }
    const double ly = mt + plot_h + mb + 18.0 * static_cast<double>(i) + 8;
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"14\" height=\"4\" fill=\"{}\"/>"
                     "<text x=\"{}\" y=\"{}\">{}{}</text>\n",
                     ml, ly, colour, ml + 20, ly + 5, html_escape(r.label),
                     std::isfinite(r.order) ? fmt::format(": fitted order {:.2f}", r.order) : std::string());
  }
  return s + "</svg>\n";
}

// The colour bar in HTML beside each map: the map's own colours at -max, 0, +max with its numbers.
std::string html_colour_bar(double max_abs) {
  const auto css = [&](double v) {
    const Rgb8 c = diverging_colour(v, max_abs);
    return fmt::format("rgb({},{},{})", c.r, c.g, c.b);
  };
  std::string s = fmt::format("<div class=\"bar\" style=\"background:linear-gradient(to right,{},{},{})\"></div>"
                              "<div class=\"ticks\">",
                              css(-max_abs), css(0), css(max_abs));
  for (double f : {-1.0, -0.5, 0.0, 0.5, 1.0}) s += "<span>" + html_escape(bar_label(f * max_abs)) + "</span>";
  return s + "</div>";
}

std::string verdict_section(const VerifyReport& rep, const HtmlReportContext& ctx) {
  const std::string verdict(verdict_name(rep.verdict.verdict));
  std::size_t images = 0;  // channels are image-major: count the image names' changes
  for (std::size_t i = 0; i < rep.channels.size(); ++i) images += i == 0 || rep.channels[i].image != rep.channels[i - 1].image;
  const std::size_t channels = images ? rep.channels.size() / images : 0;
  std::string s = fmt::format("<header id=\"verdict\" class=\"{}\">\n<p class=\"kicker\">{}: {} × {} pixels, {} images "
                              "× {} channel{}</p>\n<h1><span id=\"verdict-text\">{}</span> <span class=\"badge\">{}</span></h1>\n"
                              "<p id=\"verdict-reason\">{} ({})</p>\n",
                              rep.pass ? "pass" : "fail", html_escape(ctx.title), rep.width, rep.height, images,
                              channels, channels == 1 ? "" : "s", html_escape(verdict), rep.pass ? "PASS" : "FAIL",
                              html_escape(rep.verdict.reason), html_escape(rep.verdict_channel));
  s += "<div id=\"named-fault\">\n";
  if (rep.faults.empty()) s += "<p class=\"fault none\">No fault named.</p>\n";
  // The fitted fault is the name; "constant floor" only the symptom it explains: the name first.
  std::vector<const Fault*> faults;
  for (const Fault& f : rep.faults) faults.push_back(&f);
  std::stable_partition(faults.begin(), faults.end(), [](const Fault* f) { return f->kind == FaultKind::fitted; });
  for (const Fault* fp : faults) {
    const Fault& f = *fp;
    const std::string head = f.kind == FaultKind::fitted && !rep.fault_fits.empty()
                                 ? fmt::format("{} (fitted: explains {:.0f} % of the error)", f.behaviour,
                                               100 * rep.fault_fits.front().confirmed)
                                 : f.name();
    s += "<p class=\"fault\"><b>Fault: " + html_escape(head) + "</b><br><span class=\"evidence\">" +
         html_escape(f.evidence) + "</span></p>\n";
  }
  for (const Fault& f : rep.conventions)
    s += "<p class=\"convention\"><b>Convention: " + html_escape(f.behaviour) + "</b> — consistent with the expected order " +
         g3(rep.expected_order.value_or(NAN)) + "<br><span class=\"evidence\">" + html_escape(f.evidence) + "</span></p>\n";
  s += "</div>\n";
  if (!rep.failures.empty()) {
    s += "<ul id=\"failures\">";
    for (const std::string& f : rep.failures) s += "<li>FAIL: " + html_escape(f) + "</li>";
    s += "</ul>\n";
  }
  // Projections: their mode, and what was not run (lib/verify/projection_models.h).
  if (rep.mode) s += "<p id=\"mode\">Projection images: mode <b>" + html_escape(*rep.mode) + "</b>.</p>\n";
  for (const std::string& n : rep.notes) s += "<p class=\"note\">" + html_escape(n) + "</p>\n";
  if (!rep.diagnosis.empty())
    s += fmt::format("<p id=\"behaves-like\">Behaves like <b>{}</b> to {} RMS.</p>\n",
                     html_escape(rep.diagnosis.front().name), g3(rep.diagnosis.front().rms));
  s += fmt::format("<p class=\"small\">Expected order: {}. Reference: tolerance {} per pixel, largest error "
                   "estimate {}{}.</p>\n",
                   rep.expected_order ? g3(*rep.expected_order) : std::string("none given"), g3(rep.reference.tol),
                   g3(rep.reference.max_error_estimate),
                   rep.reference.missed ? fmt::format(", {} pixels missed it", rep.reference.missed) : std::string());
  return s + "</header>\n";
}

std::string maps_section(const VerifyReport& rep, const ScratchFolder& scratch) {
  std::string s = "<section id=\"error-maps\"><h2>Error maps</h2>\n<p>Signed error (image − reference) per image "
                  "and channel, coarsest step first; blue below the reference, red above, white exact, black "
                  "NaN. Each map's colour range is ± its own largest |error| (numbered on the bar).</p>\n"
                  "<div class=\"maps\">\n";
  const int scale = std::clamp((kShownSide + rep.height - 1) / std::max(rep.height, 1), 1, 8);
  for (std::size_t i = 0; i < rep.channels.size(); ++i) {
    const ChannelReport& c = rep.channels[i];
    Image err(rep.width, rep.height);
    std::copy(c.error.begin(), c.error.end(), err.pixels.begin());
    const double range = std::isfinite(c.all().max) ? c.all().max : 0.0;
    const fs::path png = scratch.file(fmt::format("error_{}.png", i));
    write_numbered_error_map_png(err, png, range);
    const int shown_w = numbered_error_map(Image(rep.width, 1), range).width;  // the map's width, bar and labels
    s += fmt::format("<figure><img class=\"error-map\" alt=\"signed error of {0}, channel {1}\" width=\"{2}\" "
                     "height=\"{3}\" src=\"{4}\"><figcaption><b>{0}</b> ({1}), step {5}: RMS {6}, max {7}{8}",
                     html_escape(c.image), html_escape(c.channel), shown_w * scale, rep.height * scale, data_uri(png),
                     g3(c.step), g3(c.all().rms), g3(c.all().max),
                     c.nan_count ? fmt::format(", {} NaN pixels", c.nan_count) : std::string());
    s += html_colour_bar(range) + "</figcaption></figure>\n";
  }
  // An RGB scene's reference in colour, every channel on the one scale.
  Image ref(rep.width, rep.height, 0, rep.reference_channels);
  std::copy(rep.reference_image.begin(), rep.reference_image.end(), ref.pixels.begin());
  const auto [lo, hi] = std::minmax_element(ref.pixels.begin(), ref.pixels.end());
  const double top = *hi > *lo ? *hi : *lo + 1;
  const fs::path png = scratch.file("reference.png");
  write_png_preview(ref, png, *lo, top);
  s += fmt::format("<figure><img class=\"reference\" alt=\"the reference image\" width=\"{}\" height=\"{}\" "
                   "src=\"{}\"><figcaption><b>The reference</b>, {} from {} (black) to {} (white)</figcaption>"
                   "</figure>\n",
                   rep.width * scale, rep.height * scale, data_uri(png),
                   rep.reference_channels == 3 ? "each channel" : "grey", g3(*lo), g3(top));
  return s + "</div></section>\n";
}

std::string catalogue_section(const VerifyReport& rep) {
  std::string s = "<section id=\"catalogue\"><h2>Fault catalogue</h2>\n";
  if (rep.fault_fits.empty()) {
    s += "<p id=\"catalogue-empty\">Not fitted: the catalogue decomposes a step-independent floor, and these "
         "images do not stall at one.</p>\n";
  } else {
    s += "<p>Each entry perturbs vrv's model of the renderer by one fault; its parameter is fitted by least squares "
         "to the finest image. <i>explained</i>: the fraction of the squared error against the unperturbed model "
         "it removes on the fitting pixels; <i>confirmed</i>: the same on the diagnosis pixels (the leaders).</p>\n";
    Table t({"rank", "entry", "parameter", "fitted value", "explained", "confirmed", "what the renderer does"});
    t.allow_missing("fitted value");
    long rank = 1;
    for (const FaultFit& f : rep.fault_fits)
      t.add_row({rank++, f.name, f.parameter.empty() ? std::string("none") : f.parameter, f.value, percent(f.explained),
                 percent(f.confirmed), f.description});
    s += html_table(t, "catalogue-ranking");
  }
  if (!rep.diagnosis.empty()) {
    s += "<h3>vrv's nearest models</h3>\n";
    Table t({"rank", "model", "rms", "max", "pixels"});
    t.allow_missing("rms");
    t.allow_missing("max");
    for (std::size_t k = 0; k < std::min(kShownModels, rep.diagnosis.size()); ++k) {
      const Candidate& c = rep.diagnosis[k];
      t.add_row({static_cast<long>(k + 1), c.name, c.rms, c.max, c.pixels});
    }
    s += html_table(t, "diagnosis");
    if (rep.diagnosis.size() > kShownModels)
      s += fmt::format("<p class=\"small\">and {} more (diagnosis.csv with --out).</p>\n", rep.diagnosis.size() - kShownModels);
  }
  return s + "</section>\n";
}

constexpr const char* kStyle = R"(
body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:72em;padding:0 1em;color:#222}
header{border-left:8px solid #888;padding:.5em 1em;margin-bottom:1.5em;background:#f6f6f6}
header.pass{border-color:#2a7d2a}header.fail{border-color:#b22}
h1{margin:.2em 0}.badge{font-size:.6em;padding:.1em .5em;border-radius:.3em;color:#fff;background:#888;vertical-align:middle}
.pass .badge{background:#2a7d2a}.fail .badge{background:#b22}
.kicker,.small,.evidence{color:#555;font-size:.9em}.fault b{color:#b22}.convention b{color:#2a7d2a}
table{border-collapse:collapse;margin:.5em 0;font-size:.85em}th,td{border:1px solid #ccc;padding:.15em .5em}
th{background:#eee}td.num{text-align:right;font-variant-numeric:tabular-nums}
.maps{display:flex;flex-wrap:wrap;gap:1em}figure{margin:0}figcaption{font-size:.8em;max-width:30em}
img{image-rendering:pixelated}.bar{height:10px;width:100%;max-width:20em;margin-top:.3em}
.ticks{display:flex;justify-content:space-between;max-width:20em;font-size:.9em}
.scroll{overflow-x:auto}pre{background:#f4f4f4;padding:.5em;overflow-x:auto;white-space:pre-wrap}
)";

}  // namespace

std::string html_escape(std::string_view text) {
  // Five replacements: shorter than a dependency, and the set every HTML escaper uses.
  std::string s;
  s.reserve(text.size());
  for (char c : text) switch (c) {
      case '&': s += "&amp;"; break;
      case '<': s += "&lt;"; break;
      case '>': s += "&gt;"; break;
      case '"': s += "&quot;"; break;
      case '\'': s += "&#39;"; break;
      default: s += c;
    }
  return s;
}

std::string shell_quote(std::string_view word) {
  // POSIX single-quoting, one rule; no library of ours does it.
  const bool safe = !word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::string_view("-_./,:=+@%").find(c) != std::string_view::npos;
  });
  if (safe) return std::string(word);
  std::string s = "'";
  for (char c : word) s += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return s + "'";
}

std::string base64(std::string_view bytes) {
  using namespace boost::archive::iterators;
  using Encoder = base64_from_binary<transform_width<std::string_view::const_iterator, 6, 8>>;
  std::string s(Encoder(bytes.begin()), Encoder(bytes.end()));
  return s.append((3 - bytes.size() % 3) % 3, '=');
}

std::string verify_report_html(const VerifyReport& rep, const HtmlReportContext& ctx) {
  // The image module writes files only (its interface is paths): each picture is written to a
  // private folder, read back for its base64 and the folder removed.
  const ScratchFolder scratch("vrv-report", "the report's images");
  const VerifyTables t = verify_tables(rep);
  std::string s = fmt::format("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
                              "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
                              "<title>{}: {}</title>\n<style>{}</style></head>\n<body>\n",
                              html_escape(ctx.title), html_escape(verdict_name(rep.verdict.verdict)), kStyle);
  s += verdict_section(rep, ctx);
  s += "<section id=\"convergence\"><h2>Convergence</h2>\n<p>Error (" + html_escape(metric_name(rep.order_metric)) +
       " over the image) against the sample distance, log-log; dashed: the fitted order.</p>\n" +
       convergence_svg(rep.orders) + html_table(t.orders, "orders") + "</section>\n";
  s += maps_section(rep, scratch);
  s += "<section id=\"regions\"><h2>Errors by region</h2>\n<p>silhouette: within two pixels of the volume's outline; "
       "tf_jump: rays crossing a jump of the transfer function; interior: the other rays that hit the box; "
       "fraction_over: |e| above " + g3(rep.threshold) + ".</p>\n" + html_table(t.errors, "region-table") + "</section>\n";
  if (ctx.bounds) s += "<section id=\"bounds\"><h2>Bounds</h2>\n" + html_table(*ctx.bounds, "bounds-table") + "</section>\n";
  s += catalogue_section(rep);
  s += "<section id=\"reproduce\"><h2>To reproduce</h2>\n";
  for (const std::string& c : ctx.commands) s += "<pre><code>" + html_escape(c) + "</code></pre>\n";
  s += fmt::format("<p class=\"small\">The reference image alone: <code>vrv render --reference --width {} --height {} "
                   "--tol {} -o reference.exr</code> (with the same --scene).</p>\n</section>\n",
                   rep.width, rep.height, g3(rep.reference.tol));
  return s + "</body></html>\n";
}

void check_verify_report_path(const fs::path& path, const std::vector<fs::path>& inputs, const fs::path& out_dir,
                              std::string_view option) {
  if (path.empty() || !path.has_filename())
    throw std::invalid_argument(fmt::format("{}: {}: give a file name, e.g. report.html", option, path.string()));
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw std::invalid_argument(fmt::format("{}: {}: is a directory; give a file name, e.g. {}", option, path.string(),
                                            (path / "report.html").string()));
  for (const fs::path& input : inputs)
    if (!input.empty() && same_file(path, input))
      throw std::invalid_argument(fmt::format("{}: {}: is the input {}, which the report would replace", option,
                                              path.string(), input.string()));
  if (!out_dir.empty() && same_file(path, out_dir))
    throw std::invalid_argument(fmt::format("{}: {}: is also --out; give the report a name of its own", option,
                                            path.string()));
  if (!out_dir.empty()) {
    const fs::path out = fs::weakly_canonical(fs::absolute(out_dir, ec), ec);
    for (fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec).parent_path(); !p.empty(); p = p.parent_path()) {
      if (p == out)
        throw std::invalid_argument(fmt::format("{}: {}: lies in --out {}, which is replaced whole; write the report "
                                                "elsewhere", option, path.string(), out_dir.string()));
      if (p == p.root_path()) break;
    }
  }
  const fs::path parent = fs::absolute(path, ec).parent_path();
  check_writable_dir(parent, option);
  try {
    image_module::functions();
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(fmt::format("{}: {}: the images cannot be made: {}", option, path.string(), e.what()));
  }
}

void write_verify_report_html(const fs::path& path, const VerifyReport& report, const HtmlReportContext& context) {
  write_file_atomically(path, verify_report_html(report, context));
}

}  // namespace vrv
