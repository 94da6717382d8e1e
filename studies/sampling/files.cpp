// The sampling study's tables, images and plots.json; see files.h.
#include "studies/sampling/files.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lib/io/atomic_file.h"
#include "lib/io/image_io.h"
#include "lib/io/table.h"
#include "studies/engine/study_outputs.h"

namespace vrv::sampling_study {
namespace {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

std::string rate_text(double rate) { return fmt::format("{:g}", rate); }

const StrategyRun* find_run(const std::vector<StrategyRun>& runs, SegmentRule rule, Strategy s,
                            double rate) {
  for (const StrategyRun& f : runs)
    if (f.rule == rule && f.strategy == s && f.rate == rate) return &f;
  return nullptr;
}

// rays.csv: the discrete curves at the curve rates and, per strategy, the continuous solution as
// its own series (repeated, so that each Fig. 2 panel is one `where` on one file).
Table ray_table(const Study& st, std::size_t ray_count, const std::vector<ContinuousRay>& truth,
                const std::vector<StrategyRun>& runs) {
  Table t({"strategy", "series", "rate", "ray", "angle_degrees", "chord", "samples", "intensity",
           "reference", "error"});
  t.allow_missing("rate");
  t.allow_missing("samples");
  for (Strategy s : st.strategies) {
    for (std::size_t i = 0; i < ray_count; ++i)
      t.add_row({std::string(strategy_name(s)), std::string("continuous"), kMissing,
                 static_cast<long>(i), fan_angle_degrees(st.setup, static_cast<int>(i)),
                 truth[i].chord, kMissing, truth[i].value, truth[i].value, 0.0});
    for (double rate : st.curve_rates) {
      const StrategyRun* f = find_run(runs, st.rules.front(), s, rate);
      for (std::size_t i = 0; i < ray_count; ++i)
        t.add_row({std::string(strategy_name(s)), series_name(rate), rate, static_cast<long>(i),
                   fan_angle_degrees(st.setup, static_cast<int>(i)), truth[i].chord,
                   static_cast<double>(f->rays[i].samples), f->rays[i].value, truth[i].value,
                   f->rays[i].value - truth[i].value});
    }
  }
  return t;
}

Table error_table(const Study& st, const std::vector<StrategyRun>& runs) {
  Table t({"rule", "strategy", "rate", "h", "max_error", "mean_error", "mean_samples", "rays_hit",
           "rays_dropped"});
  for (const char* c : {"max_error", "mean_error"}) t.set_format(c, "{:.3e}");
  t.set_format("mean_samples", "{:.2f}");
  for (SegmentRule rule : st.rules)
  for (Strategy s : st.strategies)
    for (double rate : st.order_rates) {
      const StrategyRun* f = find_run(runs, rule, s, rate);
      t.add_row({std::string(segment_rule_name(rule)), std::string(strategy_name(s)), rate, 1 / rate, f->stats.error.max,
                 f->stats.error.mean, f->stats.mean_samples, f->stats.error.count, f->stats.dropped});
    }
  return t;
}

// The paper has no table; this one gathers what its Fig. 2 shows per panel: errors at the
// curve rates, the rays lost at the lowest rate, and the observed orders.
Table summary_table(const Study& st, const std::vector<StrategyRun>& runs,
                    const std::vector<StrategyOrder>& orders, LatexStyle& style) {
  std::vector<std::string> cols{"rule", "strategy"};
  for (double rate : st.curve_rates) {
    cols.push_back("max_sr" + rate_text(rate));
    style.headers[cols.back()] = fmt::format("max, S.R.~{}", rate_text(rate));
  }
  for (double rate : st.curve_rates) {
    cols.push_back("mean_sr" + rate_text(rate));
    style.headers[cols.back()] = fmt::format("mean, S.R.~{}", rate_text(rate));
  }
  const std::string dropped = "dropped_sr" + rate_text(st.curve_rates.front());
  for (const std::string& c : {dropped, std::string("order_max"), std::string("order_mean")})
    cols.push_back(c);
  style.headers[dropped] = fmt::format("dropped, S.R.~{}", rate_text(st.curve_rates.front()));
  style.headers["order_max"] = "order (max)";
  style.headers["order_mean"] = "order (mean)";
  Table t(cols);
  for (const std::string& c : cols)
    if (c.starts_with("max_") || c.starts_with("mean_")) t.set_format(c, "{:.3e}");
  t.set_format("order_max", "{:.2f}");
  t.set_format("order_mean", "{:.2f}");
  t.allow_missing("order_max");
  t.allow_missing("order_mean");
  for (const StrategyOrder& o : orders) {
    std::vector<Table::Cell> row{std::string(segment_rule_name(o.rule)),
                                 std::string(strategy_name(o.strategy))};
    for (double rate : st.curve_rates)
      row.emplace_back(find_run(runs, o.rule, o.strategy, rate)->stats.error.max);
    for (double rate : st.curve_rates)
      row.emplace_back(find_run(runs, o.rule, o.strategy, rate)->stats.error.mean);
    row.emplace_back(find_run(runs, o.rule, o.strategy, st.curve_rates.front())->stats.dropped);
    row.emplace_back(o.order_max);
    row.emplace_back(o.order_mean);
    t.add_row(std::move(row));
  }
  return t;
}

}  // namespace

std::string series_name(double rate) { return "S.R. " + rate_text(rate); }

void write_fan_tables(const std::filesystem::path& dir, const Study& st, std::size_t ray_count,
                      const std::vector<ContinuousRay>& truth, const std::vector<StrategyRun>& runs,
                      const std::vector<StrategyOrder>& orders) {
  write_file_atomically(dir / "rays.csv", ray_table(st, ray_count, truth, runs).to_csv());
  LatexStyle errors_style;
  errors_style.caption = fmt::format(
      "Per-ray error $|I_\\mathrm{{discrete}} - I|$ over the {} fan rays that meet the volume "
      "per rule (riemann: eq.~(5)); $h = 1/\\mathrm{{rate}}$ in voxels.",
      runs.empty() ? 0 : runs.front().stats.error.count);
  errors_style.label = "tab:sampling-errors";
  write_table(dir, "errors", error_table(st, runs), errors_style);
  LatexStyle summary_style;
  summary_style.caption =
      "Max and mean per-ray error per strategy at the paper's sampling rates (S.R.), fan rays "
      "dropped at the lowest rate, and observed orders over all rates.";
  summary_style.label = "tab:sampling-summary";
  const Table summary = summary_table(st, runs, orders, summary_style);
  write_table(dir, "summary", summary, summary_style);
}

void write_images(const std::filesystem::path& dir, const Study& st, const Camera& view,
                  const std::vector<ContinuousRay>& truth, const std::vector<StrategyRun>& images) {
  std::vector<double> reference(truth.size());
  double peak = 0;
  for (std::size_t p = 0; p < truth.size(); ++p) {
    reference[p] = truth[p].value;
    peak = std::max(peak, reference[p]);
  }
  const double hi = peak > 0 ? peak : 1;
  write_exr(to_image(view, reference), dir / "reference.exr");
  write_png_preview(to_image(view, reference), dir / "reference.png", 0, hi);

  Table t({"strategy", "rate", "width", "height", "max_error", "mean_error", "mean_samples",
           "pixels_hit", "pixels_dropped", "colour_range"});
  for (const char* c : {"max_error", "mean_error", "colour_range"}) t.set_format(c, "{:.3e}");
  t.set_format("mean_samples", "{:.2f}");
  for (double rate : st.image_rates) {
    // One colour range per rate, so the strategies' error maps compare at a glance.
    double range = 0;
    for (const StrategyRun& im : images)
      if (im.rate == rate) range = std::max(range, im.stats.error.max);
    for (const StrategyRun& im : images) {
      if (im.rate != rate) continue;
      std::vector<double> value(truth.size()), error(truth.size());
      for (std::size_t p = 0; p < truth.size(); ++p) {
        value[p] = im.rays[p].value;
        error[p] = im.rays[p].value - truth[p].value;
      }
      const std::string stem = fmt::format("{}_r{}", strategy_name(im.strategy), rate_text(rate));
      write_exr(to_image(view, value), dir / (stem + ".exr"));
      write_png_preview(to_image(view, value), dir / (stem + ".png"), 0, hi);
      write_exr(to_image(view, error), dir / (stem + "_error.exr"));
      write_error_map_png(to_image(view, error), dir / (stem + "_error.png"), range);
      t.add_row({std::string(strategy_name(im.strategy)), rate, static_cast<long>(view.width),
                 static_cast<long>(view.height), im.stats.error.max, im.stats.error.mean,
                 im.stats.mean_samples, im.stats.error.count, im.stats.dropped, range});
    }
  }
  write_file_atomically(dir / "images.csv", t.to_csv());
  write_file_atomically(dir / "images.md", t.to_markdown());
}

void write_plots(const std::filesystem::path& dir, const Study& st) {
  nlohmann::json plots = nlohmann::json::array();
  const char* panel = "abcdefg";
  for (std::size_t k = 0; k < st.strategies.size(); ++k) {
    const std::string s(strategy_name(st.strategies[k]));
    plots.push_back({{"name", "fig2_" + s}, {"csv", "rays.csv"}, {"style", "lines"},
                     {"x", "ray"}, {"y", "intensity"}, {"group", "series"},
                     {"where", {{"strategy", s}}},
                     {"reference", {{"column", "series"}, {"value", "continuous"}}},
                     {"xlabel", "ray"}, {"ylabel", "intensity"},
                     {"title", fmt::format("Fig. 2{}: {} (continuous: vrv reference)",
                                           k < 7 ? std::string(1, panel[k]) : "", s)}});
  }
  for (double rate : st.curve_rates)
    plots.push_back({{"name", "error_sr" + rate_text(rate)}, {"csv", "rays.csv"}, {"style", "lines"},
                     {"x", "ray"}, {"y", "error"}, {"group", "strategy"},
                     {"where", {{"series", series_name(rate)}}}, {"hlines", {0}},
                     {"xlabel", "ray"}, {"ylabel", "discrete - continuous"},
                     {"title", fmt::format("Signed per-ray error, sampling rate {}", rate_text(rate))}});
  for (SegmentRule rule : st.rules)
  for (const char* y : {"max_error", "mean_error"})
    plots.push_back({{"name", fmt::format("convergence_{}_{}", segment_rule_name(rule), y)}, {"csv", "errors.csv"},
                     {"style", "lines"}, {"x", "h"}, {"y", y}, {"group", "strategy"},
                     {"where", {{"rule", std::string(segment_rule_name(rule))}}},
                     {"xscale", "log"}, {"yscale", "log"}, {"fit", true},
                     {"xlabel", "nominal step h = 1 / rate (voxels)"},
                     {"ylabel", fmt::format("{} per-ray |error|", std::string_view(y).substr(0, 4) == "max_" ? "max" : "mean")},
                     {"title", fmt::format("Convergence per placement, rule {} ({} fan rays)",
                                           segment_rule_name(rule), st.setup.rays)}});
  for (SegmentRule rule : st.rules)
    plots.push_back({{"name", fmt::format("error_vs_samples_{}", segment_rule_name(rule))},
                     {"csv", "errors.csv"}, {"style", "lines"}, {"x", "mean_samples"},
                     {"y", "mean_error"}, {"group", "strategy"},
                     {"where", {{"rule", std::string(segment_rule_name(rule))}}},
                     {"xscale", "log"}, {"yscale", "log"}, {"fit", true},
                     {"xlabel", "mean samples per ray"}, {"ylabel", "mean per-ray |error|"},
                     {"title", fmt::format("Error against work, rule {}", segment_rule_name(rule))}});
  write_file_atomically(dir / "plots.json", nlohmann::json{{"plots", plots}}.dump(2) + "\n");
}

}  // namespace vrv::sampling_study
